"""The robot's body and the differential drive that moves it.

:class:`Body` keeps the pose as a function of time between two events: a base pose at
``t0_us`` and a motion that is exact for constant wheel speeds (an arc: straight line,
turn on the spot or circle). Contacts add half-plane constraints that stop the body at a
wall while letting it slide along it (the wheels keep turning: they slip).

:class:`DiffDriveTrain` drives the body from two H-bridge channels and two DC motors:

    v = r (w_l + w_r) / 2        w = r (w_r - w_l) / track

"""

import math

from sim_plant.engine import Part
from sim_plant.motors import Bridge, DcMotor
from sim_plant.plant import NEVER_US

LAG_STEP_US = 5_000
"""Motor lag is followed in steps of this length (speeds held within a step, so arcs and
encoder edges stay exact); only while a motor with a time constant is settling."""
SETTLED_RAD_S = 1e-3


class Body:
    """Pose of the reference point (x, y, heading) between events.

    Motion since ``t0_us``: an arc of speed ``v`` (m/s) and turn rate ``w`` (rad/s), or
    (pool cleaner) a track-stop segment, see :mod:`sim_plant.physics.tracked`.
    ``constraints`` are ``(nx, ny, c, ox, oy)``: the body point at offset ``(ox, oy)``
    (body frame) must stay on the side ``n . q >= c`` of a wall it touches.
    """

    def __init__(self, x_m: float, y_m: float, theta_rad: float):
        self.t0_us = 0
        self.x0, self.y0, self.th0 = float(x_m), float(y_m), float(theta_rad)
        self.v = 0.0
        self.w = 0.0
        self.segment = None  # non-arc motion (a track-stop segment), or None
        self.constraints: tuple = ()
        self.distance_m = 0.0

    def pose_at(self, t_us: int) -> tuple[float, float, float]:
        dt = (t_us - self.t0_us) * 1e-6
        if self.segment is not None:
            x, y, th = self.segment.pose(self.x0, self.y0, self.th0, dt)
        else:
            x, y, th = _arc(self.x0, self.y0, self.th0, self.v, self.w, dt)
        for nx, ny, c, ox, oy in self.constraints:
            co, si = math.cos(th), math.sin(th)
            s = nx * (x + co * ox - si * oy) + ny * (y + si * ox + co * oy) - c
            if s < 0.0:
                x -= s * nx
                y -= s * ny
        return x, y, th

    def rebase(self, t_us: int, pose: tuple[float, float, float] | None = None) -> None:
        """Make the pose at ``t_us`` (or ``pose``) the new base; keeps the motion."""
        x, y, th = self.pose_at(t_us)
        if self.segment is None and not self.constraints:
            self.distance_m += abs(self.v) * (t_us - self.t0_us) * 1e-6
        else:
            self.distance_m += math.hypot(x - self.x0, y - self.y0)
        if pose is not None:
            x, y, th = pose
        if self.segment is not None:
            self.segment = self.segment.advanced((t_us - self.t0_us) * 1e-6)
        self.t0_us = t_us
        self.x0, self.y0, self.th0 = x, y, math.remainder(th, 2 * math.pi)

    def set_arc(self, t_us: int, v_m_s: float, w_rad_s: float) -> None:
        self.rebase(t_us)
        self.segment = None
        self.v, self.w = v_m_s, w_rad_s

    def set_segment(self, t_us: int, segment, v_bound_m_s: float, w_bound_rad_s: float) -> None:
        self.rebase(t_us)
        self.segment = segment
        self.v, self.w = v_bound_m_s, w_bound_rad_s

    def distance_at(self, t_us: int) -> float:
        """Path length travelled up to ``t_us`` (ground truth odometer)."""
        if self.segment is None and not self.constraints:
            return self.distance_m + abs(self.v) * (t_us - self.t0_us) * 1e-6
        x, y, _ = self.pose_at(t_us)
        return self.distance_m + math.hypot(x - self.x0, y - self.y0)

    def speed_bound_m_s(self, reach_m: float) -> float:
        """Upper bound of the speed of any body point within ``reach_m`` of the reference."""
        return abs(self.v) + abs(self.w) * reach_m


def _arc(x: float, y: float, th: float, v: float, w: float, dt: float) -> tuple[float, float, float]:
    """Exact motion at constant v, w: the chord of the arc, along the mid heading."""
    dth = w * dt
    if -1e-9 < dth < 1e-9:
        chord = v * dt
    else:
        chord = 2.0 * v / w * math.sin(dth / 2.0)
    mid = th + dth / 2.0
    return x + chord * math.cos(mid), y + chord * math.sin(mid), th + dth


class DiffDriveTrain(Part):
    """Two wheels on one axle, each behind a bridge and a motor.

    ``spin_slip`` is the share of a wheel's travel its encoder does not see while the
    robot spins (wheels turning opposite ways) and that wheel turns backwards: seed 002
    §5.7, "the right wheel was pushed back by the left wheel, not producing any rotation
    of the wheel encoder". ``standby`` names a pin shared by both channels (TB6612 STBY,
    active low).
    """

    FIXED_STATE = ("bridges", "motors", "inputs", "outputs")

    def __init__(
        self,
        *,
        bridges: tuple[Bridge, Bridge],
        motors: tuple[DcMotor, DcMotor],
        wheel_radius_m: float,
        track_m: float,
        start_pose=(0.0, 0.0, 0.0),
        spin_slip: float = 0.0,
        standby: str | None = None,
    ):
        if wheel_radius_m <= 0 or track_m <= 0:
            raise ValueError(f"DiffDriveTrain: wheel_radius_m ({wheel_radius_m}) and track_m ({track_m}) must be > 0")
        if not 0.0 <= spin_slip <= 1.0:
            raise ValueError(f"DiffDriveTrain: spin_slip must be within 0..1, got {spin_slip}")
        self.bridges = list(bridges)
        self.motors = list(motors)
        self.wheel_radius_m = float(wheel_radius_m)
        self.track_m = float(track_m)
        self.spin_slip = float(spin_slip)
        self.standby = standby
        self.inputs = {**bridges[0].kinds, **bridges[1].kinds}
        if standby:
            self.inputs[standby] = "level"
            for b in self.bridges:
                b.standby = True  # STBY low at reset: both channels off
        self._no_lag = all(m.time_constant_ms <= 0.0 for m in self.motors)
        self.body = Body(*start_pose)
        self.wheel_rad_s = [0.0, 0.0]
        self.target_rad_s = [0.0, 0.0]
        self.driven = [False, False]
        self.next_us = NEVER_US

    # -- inputs ---------------------------------------------------------------------

    def set_input(self, name: str, value, t_us: int, plant) -> bool:
        """Latch a bridge pin; the speeds follow in :meth:`settle`, once for all the pins
        a board sets at the same instant."""
        if name == self.standby:
            for b in self.bridges:
                b.standby = not int(value)
            return True
        for b in self.bridges:
            role = b.pins.get(name)
            if role is not None:
                if b.state[role] == int(value):
                    return False
                b.set_pin(role, value)
                return True
        return False

    def settle(self, t_us: int, plant) -> bool:
        (duty_l, brake_l), (duty_r, brake_r) = self.bridges[0].effective(), self.bridges[1].effective()
        target = [self.motors[0].steady_rad_s(duty_l), self.motors[1].steady_rad_s(duty_r)]
        self.target_rad_s = target
        self.driven = [brake_l or duty_l != 0.0, brake_r or duty_r != 0.0]
        if target == self.wheel_rad_s:
            return False
        if self._no_lag:
            self.wheel_rad_s = list(target)
            self._apply(t_us)
            return True
        if self.next_us == NEVER_US:
            self.next_us = t_us + LAG_STEP_US
        return False

    def fire(self, t_us: int, plant, out: list) -> None:
        """One step of the motors' first-order lag."""
        settled = True
        for i in (0, 1):
            target, w = self.target_rad_s[i], self.wheel_rad_s[i]
            w += (target - w) * self.motors[i].lag_factor(LAG_STEP_US, coasting=not self.driven[i])
            if abs(target - w) < SETTLED_RAD_S:
                w = target
            else:
                settled = False
            self.wheel_rad_s[i] = w
        self._apply(t_us)
        self.next_us = NEVER_US if settled else t_us + LAG_STEP_US

    def _apply(self, t_us: int) -> None:
        wl, wr = self.wheel_rad_s
        r = self.wheel_radius_m
        self.body.set_arc(t_us, r * (wl + wr) / 2.0, r * (wr - wl) / self.track_m)

    # -- what the rest of the plant asks ----------------------------------------------

    def encoder_rad_s(self) -> tuple[float, float]:
        """Speed of each wheel's encoder disk (wheel speed less the slip it does not see)."""
        wl, wr = self.wheel_rad_s
        if self.spin_slip and wl * wr < 0.0:
            k = 1.0 - self.spin_slip
            return (wl * k, wr) if wl < 0.0 else (wl, wr * k)
        return wl, wr

    def truth(self, t_us: int, plant) -> dict:
        wl, wr = self.wheel_rad_s
        r = self.wheel_radius_m
        return {
            "v_m_s": r * (wl + wr) / 2.0,
            "w_rad_s": r * (wr - wl) / self.track_m,
            "wheel_rad_s": (wl, wr),
            "distance_m": self.body.distance_at(t_us),
        }


class SlipDriveTrain(DiffDriveTrain):
    """The differential drive with wheel slip: each wheel's encoder sees its travel over
    the floor times ``1 + slip[i]`` (spin slip comes on top)."""

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.slip = [0.0, 0.0]

    def encoder_rad_s(self) -> tuple[float, float]:
        wl, wr = super().encoder_rad_s()
        return wl * (1.0 + self.slip[0]), wr * (1.0 + self.slip[1])


class WheelSlip(Part):
    """Draws each wheel's slip every ``period_us`` (the drive then re-plans the encoders)."""

    def __init__(self, sd: float, period_us: int):
        if sd < 0 or period_us <= 0:
            raise ValueError(f"wheel_slip_sd must be >= 0 and slip_period_us > 0, got {sd}, {period_us}")
        self.sd = float(sd)
        self.period_us = int(period_us)
        self.next_us = 0
        self.changed = False

    def fire(self, t_us: int, plant, out: list) -> None:
        plant.drive.slip = [float(s) for s in plant.rng.normal(0.0, self.sd, 2)]
        self.changed = True
        self.next_us = t_us + self.period_us

    def truth(self, t_us: int, plant) -> dict:
        return {"wheel_slip": tuple(plant.drive.slip)}
