"""Seed 002's tether snag (§5.7): the robot pulls a 20 m fibre-optic tether; in two of
twenty runs it "caught on walls thus pulling the robot out of position", so that it
could not turn correctly. Modelled at the corners, where the tether bends round a wall
edge: each time the robot starts a spin on the spot (the wheels turning opposite ways),
with probability ``p_snag`` the tether catches (at every spin, or only at the spin
numbers in ``spins``), and ``delay_ms`` later it pulls the body
back along the tether by ``pull_m`` and twists it by ``twist_deg`` (each scaled by a
uniform 0.5..1.0 draw, the twist's sign drawn too). The encoders see nothing of it.

The rate is the seed's failures, not a guess at its snags: two failures in twenty runs,
both from the tether, is 0.1 a run. Not every snag costs a run here: with a snag forced
at the spin into the branch, 4 of seeds 1-10 failed (the robot drives into the branch
askew, or is pulled back across the opening); forced at the spin out of it, none of the
ten did (the centring straightens the robot on the way home). So a snag costs a run 0.2
of the time, a run must snag with chance 0.5 to fail 0.1 of the time, and with two
spins a run that is ``1 - sqrt(0.5)`` = 0.29 a spin (``P_SNAG``). Over twenty runs the
number of failures is then binomial (20, 0.1): 16 to 20 successes 96 % of the time, 18
the likeliest. ``hil_tests/test_duct.py`` measures the cost of a snag again (make hil).

The draws for the first ``MAX_SPINS`` spins are taken from the plant's generator once, at
reset, before the run moves: whether a run's k-th spin snags depends on the seed and
``p_snag`` only, not on how the firmware's timing or the drive model shifted the other
parts' use of the generator (a change to either would otherwise reshuffle which runs
snag).

Every snag is logged in ``events`` as (t_us, x, y, theta before, x, y, theta after).
"""

import math

from sim_plant.engine import Part
from sim_plant.plant import NEVER_US

COST = 0.2  # share of snags that cost the run (forced snags, module doc)
P_SNAG = 1.0 - math.sqrt(1.0 - 0.1 / COST)  # 0.29 a spin: 0.1 failures a run of two spins
MAX_SPINS = 16  # draws taken at reset; a spin past these never snags


class TetherSnag(Part):
    FIXED_STATE = ("inputs", "outputs", "draws")

    def __init__(self, *, p_snag=P_SNAG, pull_m=0.08, twist_deg=25.0, delay_ms=150, spins=None):
        self.p_snag = float(p_snag)
        self.only = None if spins is None else frozenset(int(k) for k in spins)  # spin numbers (0 first) that may snag
        self.pull_m = float(pull_m)
        self.twist_rad = math.radians(twist_deg)
        self.delay_us = int(delay_ms * 1000)
        self.spinning = False
        self.pending = None  # (scale_pull, scale_twist, sign)
        self.next_us = NEVER_US
        self.spins = 0
        self.events: list[tuple] = []
        self.draws: list[list[float]] = []

    def start(self, t_us: int, plant) -> None:
        self.draws = plant.rng.random((MAX_SPINS, 4)).tolist()  # (chance, pull, twist, sign) a spin

    def on_motion_change(self, t_us: int, plant) -> None:
        wl, wr = plant.drive.wheel_rad_s
        spinning = wl * wr < 0.0
        if spinning and not self.spinning:
            u, a, b, s = self.draws[self.spins] if self.spins < len(self.draws) else (1.0, 0.0, 0.0, 0.0)
            self.spins += 1
            if u < self.p_snag and (self.only is None or self.spins - 1 in self.only):
                self.pending = (0.5 + 0.5 * a, 0.5 + 0.5 * b, 1.0 if s < 0.5 else -1.0)
                self.next_us = t_us + self.delay_us
        self.spinning = spinning

    def fire(self, t_us: int, plant, out: list) -> None:
        self.next_us = NEVER_US
        if self.pending is None:
            return
        k_pull, k_twist, sign = self.pending
        self.pending = None
        body = plant.drive.body
        x, y, th = body.pose_at(t_us)
        nx = x - math.cos(th) * self.pull_m * k_pull  # dragged back, the way it came
        ny = y - math.sin(th) * self.pull_m * k_pull
        nth = th + sign * self.twist_rad * k_twist
        body.constraints = ()
        body.rebase(t_us, (nx, ny, nth))
        for part in plant.parts:  # what the body touches where it was pulled to, at once
            if hasattr(part, "check_us"):
                part.check_us = t_us
        self.events.append((t_us, x, y, th, nx, ny, nth))
        plant._motion_changed(t_us)

    def truth(self, t_us: int, plant) -> dict:
        return {"snags": len(self.events), "spins": self.spins}
