"""Seed 002's tether snag (§5.7): the robot pulls a 20 m fibre-optic tether; in two of
twenty runs it "caught on walls thus pulling the robot out of position", so that it
could not turn correctly. Modelled at the corners, where the tether bends round a wall
edge: each time the robot starts a spin on the spot (the wheels turning opposite ways),
with probability ``p_snag`` the tether catches, and ``delay_ms`` later it pulls the body
back along the tether by ``pull_m`` and twists it by ``twist_deg`` (each scaled by a
uniform 0.5..1.0 draw, the twist's sign drawn too). The encoders see nothing of it.

Every snag is logged in ``events`` as (t_us, x, y, theta before, x, y, theta after).
"""

import math

from sim_plant.engine import Part
from sim_plant.plant import NEVER_US


class TetherSnag(Part):
    FIXED_STATE = ("inputs", "outputs")

    def __init__(self, *, p_snag=0.1, pull_m=0.08, twist_deg=25.0, delay_ms=150):
        self.p_snag = float(p_snag)
        self.pull_m = float(pull_m)
        self.twist_rad = math.radians(twist_deg)
        self.delay_us = int(delay_ms * 1000)
        self.spinning = False
        self.pending = None  # (scale_pull, scale_twist, sign)
        self.next_us = NEVER_US
        self.spins = 0
        self.events: list[tuple] = []

    def on_motion_change(self, t_us: int, plant) -> None:
        wl, wr = plant.drive.wheel_rad_s
        spinning = wl * wr < 0.0
        if spinning and not self.spinning:
            self.spins += 1
            u, a, b, s = plant.rng.random(4).tolist()
            if u < self.p_snag:
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
