"""The WEDA B400 pool cleaner's tracks (seeds 000/001).

Both tracks run at the same speed, forwards or backwards; there is no speed control. The
machine steers only when the controller *stops* one track (a parallel-port bit per
track); its own bumper logic reverses both tracks at the end walls.

Steering follows the measured law of seed 000 §7.2, eq. 7.1 (:class:`MeasuredStopLaw`):

    theta(t) = 8.17e-6 t^2 + 0.0022 t        (degrees, t = stop time in ms)

"for the first few instants the stopped track will slip for a while, then it will start to
adhere more and more to the floor": the stopped track is dragged at ``v - W omega`` and the
heading turns at ``d theta/dt``, until that rate reaches the kinematic limit ``v / W`` of a
pivot about the stopped track (after about 2.5 s), which it then keeps. Each stop draws a
gain from N(1, ``scatter_rel``): the scatter of the 50 trials of Table 7.2 (pooled
within-time relative standard deviation 0.13; residual 0.45 deg about the law).
:class:`IdealPivotLaw` is the textbook model (eq. 4.16, pivot about the stopped track on
radius W/2). Left and right stops are alike (Table 7.2 is symmetric; the code's
``R_L = 1.5`` is a controller choice).

With signed track speeds the geometry holds in both travel directions: stopping the left
track bends the path towards the robot's left whether it runs forwards or backwards
(seed 000 §4.2's sign convention).

At an end wall the leading bumper closes; the machine stops (pump and tracks) for
``reversal_pause_ms``, floats, and resumes in the other direction with a heading kick
drawn from N(-1.74e-2 rad, 3.48e-2 rad): seed 000 §5.4 / Table 5.1, "the angle had a
negative mean value because of the pump which revolves anti-clockwise". The thesis calls
3.48e-2 a variance; read literally (sd 10.7 deg) it contradicts Table 5.1, whose six
trials lie within +-2e-2 rad, so it is taken here as the standard deviation.

=========================  ===========  ==================================================
attribute                  default      source
=========================  ===========  ==================================================
``speed_m_s``              0.3          B400 datasheet, "It can move at a speed of 0.3 m/s"
``track_m`` (W)            0.4          ``#define WIDTH .4`` (seed 000 App. A)
``reversal_pause_ms``      1000         not in the seeds (the controller waits 4000 ms)
``kick_mean_rad``          -0.0174      Table 5.1 / §5.4
``kick_sd_rad``            0.0348       Table 5.1 / §5.4 (see above)
=========================  ===========  ==================================================
"""

import math

from sim_plant.drivetrain import Body
from sim_plant.engine import Part
from sim_plant.plant import NEVER_US

DEG = math.pi / 180.0
GL_NODES = (-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526)
GL_WEIGHTS = (0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538)
MAX_QUADRATURE_STEP_RAD = 0.25


class MeasuredStopLaw:
    """theta(t) = a t^2 + b t, degrees with t in ms (seed 000 eq. 7.1), with per-stop scatter."""

    def __init__(self, a_deg_per_ms2: float = 8.17e-6, b_deg_per_ms: float = 0.0022, scatter_rel: float = 0.13):
        self.a_deg_per_ms2 = float(a_deg_per_ms2)
        self.b_deg_per_ms = float(b_deg_per_ms)
        self.scatter_rel = float(scatter_rel)

    def angle_deg(self, t_ms: float) -> float:
        return self.a_deg_per_ms2 * t_ms * t_ms + self.b_deg_per_ms * t_ms

    def stop_time_ms(self, angle_deg: float) -> float:
        """Inverse of the law: the stop that turns ``angle_deg``."""
        a, b = self.a_deg_per_ms2, self.b_deg_per_ms
        return (-b + math.sqrt(b * b + 4.0 * a * angle_deg)) / (2.0 * a)

    def draw_gain(self, rng) -> float:
        if self.scatter_rel <= 0.0:
            return 1.0
        return min(max(1.0 + self.scatter_rel * float(rng.standard_normal()), 0.2), 2.0)

    def saturation_ms(self, gain: float, pivot_rad_s: float) -> float:
        """Stop time at which the law's turn rate reaches the pivot rate ``v / W``."""
        rate_deg_per_ms = pivot_rad_s / DEG / 1000.0 / gain
        return max(0.0, (rate_deg_per_ms - self.b_deg_per_ms) / (2.0 * self.a_deg_per_ms2))


class IdealPivotLaw:
    """Kinematic steering, seed 000 eq. 4.16: delta theta = v T_c / W (a pivot at once)."""

    def draw_gain(self, rng) -> float:
        return 1.0

    def saturation_ms(self, gain: float, pivot_rad_s: float) -> float:
        return 0.0


class StopSegment:
    """Motion while one track is stopped, before the law saturates.

    Heading ``th(u) = th0 + c1 u + c2 u^2`` (u in s since the segment's base); the centre
    moves along the heading at ``sv - kw2 * omega(u)``; integrated exactly except for
    ``int cos(th)``, ``int sin(th)`` (4-point Gauss-Legendre per 0.25 rad of turn).
    """

    def __init__(self, sv: float, sigma_gain: float, tau0_ms: float, law: MeasuredStopLaw, kw2: float):
        self.sv = sv
        self.sigma_gain = sigma_gain
        self.tau0_ms = tau0_ms
        self.law = law
        self.kw2 = kw2
        k = sigma_gain * DEG
        self.c2 = k * law.a_deg_per_ms2 * 1e6
        self.c1 = k * (2.0 * law.a_deg_per_ms2 * tau0_ms + law.b_deg_per_ms) * 1e3

    def pose(self, x0: float, y0: float, th0: float, dt: float) -> tuple[float, float, float]:
        c1, c2 = self.c1, self.c2
        th1 = th0 + c1 * dt + c2 * dt * dt
        n = 1 + int(abs(th1 - th0) / MAX_QUADRATURE_STEP_RAD)
        h = dt / n
        ic = is_ = 0.0
        for k in range(n):
            u0 = k * h
            for node, weight in zip(GL_NODES, GL_WEIGHTS):
                u = u0 + h * (node + 1.0) / 2.0
                th = th0 + c1 * u + c2 * u * u
                ic += weight * math.cos(th)
                is_ += weight * math.sin(th)
        ic *= h / 2.0
        is_ *= h / 2.0
        x = x0 + self.sv * ic - self.kw2 * (math.sin(th1) - math.sin(th0))
        y = y0 + self.sv * is_ + self.kw2 * (math.cos(th1) - math.cos(th0))
        return x, y, th1

    def advanced(self, dt: float) -> "StopSegment":
        return StopSegment(self.sv, self.sigma_gain, self.tau0_ms + dt * 1000.0, self.law, self.kw2)


class TrackDrive(Part):
    """Inputs ``track_l.stop`` and ``track_r.stop`` (1 = stop that track, as the
    parallel-port bits of seed 000); the machine's own reversal logic (see the module)."""

    def __init__(
        self,
        *,
        law=None,
        speed_m_s: float = 0.3,
        track_m: float = 0.4,
        start_pose=(0.0, 0.0, 0.0),
        reversal_pause_ms: float = 1000.0,
        kick_mean_rad: float = -0.0174,
        kick_sd_rad: float = 0.0348,
        stop_names=("track_l.stop", "track_r.stop"),
    ):
        self.law = law if law is not None else MeasuredStopLaw()
        self.speed_m_s = float(speed_m_s)
        self.track_m = float(track_m)
        self.pivot_rad_s = self.speed_m_s / self.track_m
        self.reversal_pause_us = int(reversal_pause_ms * 1000)
        self.kick_mean_rad = float(kick_mean_rad)
        self.kick_sd_rad = float(kick_sd_rad)
        self.stop_names = tuple(stop_names)
        self.inputs = dict.fromkeys(self.stop_names, "level")
        self.body = Body(*start_pose)
        self.direction = 1  # +1 forwards, -1 backwards
        self.stopped = [0, 0]
        self.stop_side = -1  # track stopped alone (0 left, 1 right), -1 none
        self.stop_start_us = 0
        self.stop_gain = 1.0
        self.saturate_us = NEVER_US
        self.pause_end_us = NEVER_US
        self.pending_direction = 1
        self.reversals = 0
        self.kicks: list[float] = []
        self.next_us = NEVER_US

    @property
    def paused(self) -> bool:
        return self.pause_end_us != NEVER_US

    def start(self, t_us: int, plant) -> None:
        """The machine runs from the start (the controller only stops tracks)."""
        self._replan(t_us, plant.rng)

    def set_input(self, name: str, value, t_us: int, plant) -> bool:
        i = self.stop_names.index(name)
        level = 1 if int(value) else 0
        if level == self.stopped[i]:
            return False
        self.stopped[i] = level
        return self._replan(t_us, plant.rng)

    def start_reversal(self, t_us: int, new_direction: int) -> bool:
        """The leading bumper closed: stop, float, then run the other way."""
        if self.paused or new_direction == self.direction:
            return False
        self.pause_end_us = t_us + self.reversal_pause_us
        self.pending_direction = new_direction
        self.stop_side = -1
        self.saturate_us = NEVER_US
        self.body.set_arc(t_us, 0.0, 0.0)
        self._schedule()
        return True

    def fire(self, t_us: int, plant, out: list) -> None:
        if t_us >= self.pause_end_us:
            self.pause_end_us = NEVER_US
            kick = self.kick_mean_rad + self.kick_sd_rad * float(plant.rng.standard_normal())
            self.kicks.append(kick)
            x, y, th = self.body.pose_at(t_us)
            self.body.rebase(t_us, (x, y, th + kick))
            self.direction = self.pending_direction
            self.reversals += 1
            self._replan(t_us, plant.rng)
        elif t_us >= self.saturate_us:
            self.saturate_us = NEVER_US
            self._set_pivot(t_us)
            self._schedule()

    def _replan(self, t_us: int, rng) -> bool:
        """Set the body's motion for the current inputs; True (the motion changed)."""
        if self.paused:
            return False
        left, right = self.stopped
        sv = self.direction * self.speed_m_s
        if left and right:
            self.stop_side = -1
            self.saturate_us = NEVER_US
            self.body.set_arc(t_us, 0.0, 0.0)
        elif not left and not right:
            self.stop_side = -1
            self.saturate_us = NEVER_US
            self.body.set_arc(t_us, sv, 0.0)
        else:
            side = 0 if left else 1
            if side != self.stop_side:  # a new stop begins
                self.stop_side = side
                self.stop_start_us = t_us
                self.stop_gain = self.law.draw_gain(rng)
                sat_ms = self.law.saturation_ms(self.stop_gain, self.pivot_rad_s)
                self.saturate_us = t_us + math.ceil(sat_ms * 1000.0) if sat_ms > 0.0 else NEVER_US
                if self.saturate_us == NEVER_US:
                    self._set_pivot(t_us)
                else:
                    kappa = 1.0 if side == 0 else -1.0
                    sigma = self.direction * kappa
                    seg = StopSegment(sv, sigma * self.stop_gain, 0.0, self.law, kappa * self.track_m / 2.0)
                    self.body.set_segment(t_us, seg, self.speed_m_s, self.pivot_rad_s)
            else:
                return False
        self._schedule()
        return True

    def _set_pivot(self, t_us: int) -> None:
        """Pivot about the stopped track: centre at v/2, turn rate +-v/W."""
        kappa = 1.0 if self.stop_side == 0 else -1.0
        sv = self.direction * self.speed_m_s
        self.body.set_arc(t_us, sv / 2.0, self.direction * kappa * self.pivot_rad_s)

    def _schedule(self) -> None:
        self.next_us = min(self.pause_end_us, self.saturate_us)

    def encoder_rad_s(self) -> tuple[float, float]:
        return 0.0, 0.0  # the B400 has no encoders (seed 000 §1.3.3)

    def truth(self, t_us: int, plant) -> dict:
        return {
            "direction": self.direction,
            "reversing": self.paused,
            "track_stopped": tuple(self.stopped),
            "reversals": self.reversals,
            "reversal_kicks_rad": list(self.kicks),
            "distance_m": self.body.distance_at(t_us),
            "v_m_s": self.body.v if self.body.segment is None else None,
        }
