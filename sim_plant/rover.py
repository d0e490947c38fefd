"""A first plant: a round differential-drive rover in a rectangular room.

The robot is a disc (vacuum-cleaner shape) with two driven wheels behind TB6612-style
H-bridges (IN1/IN2 direction pins + PWM), a quadrature encoder on each wheel, one
front-looking analog sonar read through an ADC, and a front bumper switch.

Wheel speeds follow the commanded duty at once (no motor lag); between input changes
they are constant, so the pose follows exact arcs and encoder edges fall at exactly
computable times. The fuller drive-train models live beside this one.

Parameters (units in the names):

=======================  =========  ==================================================
name                     default    meaning
=======================  =========  ==================================================
``room_w_m, room_h_m``   5.0, 4.0   room interior, walls at x=0, x=w, y=0, y=h
``body_radius_m``        0.17       disc radius; the bumper is the front 140 degrees
``wheel_radius_m``       0.033      driven wheel radius
``track_m``              0.23       distance between the wheels
``v_max_m_s``            0.5        wheel rim speed at full duty
``deadband_duty``        0.08       duty fraction below which a wheel does not turn
``encoder_cpr``          20         quadrature cycles per wheel revolution (80 edges)
``sonar_period_us``      500_000    a new sonar range every 500 ms
``sonar_phase_us``       20_000     first sample time
``sonar_noise_m``        0.01       standard deviation of the range noise
``sonar_min_m``          0.03       closest range the sonar reports
``sonar_max_m``          4.0        farthest range (reported when nothing is nearer)
``adc_bits``             12         ADC resolution; ``read_u16`` scales it to 16 bits
``adc_vref``             3.3        ADC full-scale volts
=======================  =========  ==================================================

Sonar volts follow the MaxBotix LV analog law, Vcc/512 per inch at 3.3 V.
"""

import math

import numpy as np

from sim_plant.plant import NEVER_US, Change, Plant

SONAR_V_PER_M = 3.3 / 512 / 0.0254
"""MaxBotix LV-style analog output: Vcc/512 per inch, at Vcc = 3.3 V."""

BUMPER_HALF_ARC_RAD = math.radians(70)
CONTACT_RECHECK_US = 5_000
MIN_STEP_US = 1_000
QUAD_A = (0, 1, 1, 0)  # quadrature levels by state; A leads B going forward
QUAD_B = (0, 0, 1, 1)
ENCODER_SIGNALS = (("enc_l.a", "enc_l.b"), ("enc_r.a", "enc_r.b"))


class RoverRoom(Plant):
    inputs = {
        "motor_l.in1": "level",
        "motor_l.in2": "level",
        "motor_l.pwm": "duty",
        "motor_r.in1": "level",
        "motor_r.in2": "level",
        "motor_r.pwm": "duty",
    }
    outputs = {
        "enc_l.a": "level",
        "enc_l.b": "level",
        "enc_r.a": "level",
        "enc_r.b": "level",
        "sonar.adc": "u16",
        "bumper": "level",
    }

    def __init__(self, *, room_w_m=5.0, room_h_m=4.0, start_pose=(1.0, 2.0, 0.0),
                 body_radius_m=0.17, wheel_radius_m=0.033, track_m=0.23, v_max_m_s=0.5,
                 deadband_duty=0.08, encoder_cpr=20, sonar_period_us=500_000,
                 sonar_phase_us=20_000, sonar_noise_m=0.01, sonar_min_m=0.03,
                 sonar_max_m=4.0, adc_bits=12, adc_vref=3.3):
        self.room_w_m = float(room_w_m)
        self.room_h_m = float(room_h_m)
        self.start_pose = tuple(float(v) for v in start_pose)
        self.body_radius_m = body_radius_m
        self.wheel_radius_m = wheel_radius_m
        self.track_m = track_m
        self.v_max_m_s = v_max_m_s
        self.deadband_duty = deadband_duty
        self.edge_rad = 2 * math.pi / (4 * encoder_cpr)
        self.sonar_period_us = sonar_period_us
        self.sonar_phase_us = sonar_phase_us
        self.sonar_noise_m = sonar_noise_m
        self.sonar_min_m = sonar_min_m
        self.sonar_max_m = sonar_max_m
        self.adc_max = (1 << adc_bits) - 1
        self.adc_bits = adc_bits
        self.adc_vref = adc_vref
        self.reset(0)

    # -- contract -------------------------------------------------------------------

    def reset(self, seed: int) -> None:
        self.rng = np.random.default_rng(seed)
        self._t_us = 0
        self.x_m, self.y_m, self.theta_rad = self.start_pose
        self.wheel_rad = [0.0, 0.0]  # wheel angles, left and right
        self.wheel_w = [0.0, 0.0]  # wheel angular speeds, rad/s
        self.drive = {name: 0 for name in self.inputs}
        self.next_sample_us = self.sonar_phase_us
        self.sonar_range_m = self.sonar_max_m
        self.levels = {"enc_l.a": 0, "enc_l.b": 0, "enc_r.a": 0, "enc_r.b": 0, "bumper": 1}
        self.adc_u16 = self._range_to_u16(self.sonar_max_m)
        self.distance_m = 0.0
        self.contacts: list[tuple[int, float, float]] = []
        self.levels["bumper"] = 0 if self._front_contact() else 1
        self._next_change = None

    @property
    def t_us(self) -> int:
        return self._t_us

    def set_input(self, name: str, value: int) -> None:
        if name not in self.inputs:
            raise KeyError(f"{type(self).__name__} has no input {name!r}; inputs: {sorted(self.inputs)}")
        self.drive[name] = int(value)
        for side, wheel in (("l", 0), ("r", 1)):
            self.wheel_w[wheel] = self._wheel_speed(side)
        self._next_change = None

    def next_change_us(self) -> int:
        if self._next_change is None:  # cached until the time or an input changes
            t = self.next_sample_us
            for wheel in (0, 1):
                t = min(t, self._t_us + self._next_edge_dt_us(wheel))
            self._next_change = min(t, self._t_us + self._contact_check_dt_us())
        return self._next_change

    def advance_to(self, t_us: int) -> list[Change]:
        changes: list[Change] = []
        while self._t_us < t_us:
            # encoder edges between two pose updates are computed in closed form; the
            # pose is updated at sonar samples, bumper checks and the end
            t_stop = min(t_us, self.next_sample_us, self._t_us + self._contact_check_dt_us())
            self._encoder_edges(t_stop, changes)
            self._move(t_stop)
            self._emit(changes)
        return changes

    def _encoder_edges(self, t_stop: int, changes: list[Change]) -> None:
        t0 = self._t_us
        dt_s = (t_stop - t0) / 1e6
        edges = []
        for wheel, (name_a, name_b) in enumerate(ENCODER_SIGNALS):
            w = self.wheel_w[wheel]
            if w == 0.0:
                continue
            phi0 = self.wheel_rad[wheel]
            k0 = math.floor(phi0 / self.edge_rad)
            k1 = math.floor((phi0 + w * dt_s) / self.edge_rad)
            ks = range(k0 + 1, k1 + 1) if w > 0 else range(k0, k1, -1)
            for k in ks:
                t_e = t0 + max(1, math.ceil((k * self.edge_rad - phi0) / w * 1e6))
                state = (k if w > 0 else k - 1) % 4
                edges.append((min(t_e, t_stop), wheel, name_a, name_b, state))
        if len(edges) > 1:
            edges.sort(key=lambda e: (e[0], e[1]))
        levels = self.levels
        for t_e, _wheel, name_a, name_b, state in edges:
            a, b = QUAD_A[state], QUAD_B[state]
            if levels[name_a] != a:
                levels[name_a] = a
                changes.append(Change(t_e, name_a, a))
            if levels[name_b] != b:
                levels[name_b] = b
                changes.append(Change(t_e, name_b, b))

    _SCALARS = ("_t_us", "x_m", "y_m", "theta_rad", "next_sample_us", "sonar_range_m", "adc_u16", "distance_m",
                "_next_change")

    def snapshot(self):
        """The whole mutable state, for the runner's rollback of a speculative batch."""
        return ([getattr(self, k) for k in self._SCALARS], list(self.wheel_rad), list(self.wheel_w), dict(self.drive),
                dict(self.levels), len(self.contacts), self.rng.bit_generator.state)

    def restore(self, snap) -> None:
        scalars, wheel_rad, wheel_w, drive, levels, n_contacts, rng_state = snap
        for key, value in zip(self._SCALARS, scalars):
            setattr(self, key, value)
        self.wheel_rad, self.wheel_w, self.drive, self.levels = list(wheel_rad), list(wheel_w), dict(drive), dict(levels)
        del self.contacts[n_contacts:]
        self.rng.bit_generator.state = rng_state

    def output(self, name: str) -> object:
        if name == "sonar.adc":
            return self.adc_u16
        return self.levels[name]

    def truth(self) -> dict:
        return {
            "t_us": self._t_us,
            "x_m": self.x_m,
            "y_m": self.y_m,
            "theta_rad": self.theta_rad,
            "v_m_s": self.wheel_radius_m * (self.wheel_w[0] + self.wheel_w[1]) / 2,
            "distance_m": self.distance_m,
            "sonar_range_m": self.sonar_range_m,
            "bumper_pressed": self.levels["bumper"] == 0,
            "contacts": list(self.contacts),
        }

    # -- physics --------------------------------------------------------------------

    def _wheel_speed(self, side: str) -> float:
        direction = self.drive[f"motor_{side}.in1"] - self.drive[f"motor_{side}.in2"]
        duty = min(max(self.drive[f"motor_{side}.pwm"], 0), 65535) / 65535
        if direction == 0 or duty <= self.deadband_duty:
            return 0.0
        frac = (duty - self.deadband_duty) / (1 - self.deadband_duty)
        return direction * frac * self.v_max_m_s / self.wheel_radius_m

    def _next_edge_dt_us(self, wheel: int) -> int:
        w = self.wheel_w[wheel]
        if w == 0.0:
            return NEVER_US
        phi = self.wheel_rad[wheel]
        k = math.floor(phi / self.edge_rad)
        boundary = (k + 1) * self.edge_rad if w > 0 else k * self.edge_rad
        dt_us = math.ceil((boundary - phi) / w * 1e6)
        return max(dt_us, 1)

    def _wall_gaps_m(self) -> tuple[float, float, float, float]:
        r = self.body_radius_m
        return (self.x_m - r, self.room_w_m - r - self.x_m, self.y_m - r, self.room_h_m - r - self.y_m)

    def _contact_check_dt_us(self) -> int:
        if self.levels["bumper"] == 0:
            return CONTACT_RECHECK_US
        speed = self.wheel_radius_m * (abs(self.wheel_w[0]) + abs(self.wheel_w[1])) / 2
        if speed == 0.0:
            return NEVER_US
        gap_m = max(min(self._wall_gaps_m()), 0.0)
        return max(int(gap_m / speed * 1e6), MIN_STEP_US)

    def _move(self, t_us: int) -> None:
        dt_s = (t_us - self._t_us) / 1e6
        wl, wr = self.wheel_w
        self.wheel_rad[0] += wl * dt_s
        self.wheel_rad[1] += wr * dt_s
        v = self.wheel_radius_m * (wl + wr) / 2
        w = self.wheel_radius_m * (wr - wl) / self.track_m
        th0 = self.theta_rad
        if abs(w) < 1e-12:
            dx, dy = v * dt_s * math.cos(th0), v * dt_s * math.sin(th0)
        else:  # exact arc for constant v, w
            th1 = th0 + w * dt_s
            dx = v / w * (math.sin(th1) - math.sin(th0))
            dy = -v / w * (math.cos(th1) - math.cos(th0))
        r = self.body_radius_m
        x1 = min(max(self.x_m + dx, r), self.room_w_m - r)  # walls stop the body; wheels slip
        y1 = min(max(self.y_m + dy, r), self.room_h_m - r)
        self.distance_m += math.hypot(x1 - self.x_m, y1 - self.y_m)
        self.x_m, self.y_m = x1, y1
        self.theta_rad = math.remainder(th0 + w * dt_s, 2 * math.pi)
        self._t_us = t_us
        self._next_change = None

    def _front_contact(self) -> bool:
        gaps = self._wall_gaps_m()
        normals = (math.pi, 0.0, -math.pi / 2, math.pi / 2)  # direction towards each wall
        for gap, toward in zip(gaps, normals):
            if gap <= 1e-9 and abs(math.remainder(toward - self.theta_rad, 2 * math.pi)) <= BUMPER_HALF_ARC_RAD:
                return True
        return False

    def _emit(self, changes: list[Change]) -> None:
        """Bumper and sonar outputs at the current time (encoder edges come from
        _encoder_edges, which knows their exact times)."""
        t = self._t_us
        bumper = 0 if self._front_contact() else 1
        if bumper != self.levels["bumper"]:
            self.levels["bumper"] = bumper
            changes.append(Change(t, "bumper", bumper))
            if bumper == 0:
                self.contacts.append((t, self.x_m, self.y_m))
        if t >= self.next_sample_us:
            self.sonar_range_m = self._sonar_range_m()
            self.adc_u16 = self._range_to_u16(self.sonar_range_m)
            changes.append(Change(t, "sonar.adc", self.adc_u16))
            self.next_sample_us += self.sonar_period_us

    # -- sensors --------------------------------------------------------------------

    def _sonar_range_m(self) -> float:
        """Range from the body's front to the wall straight ahead, with noise."""
        c, s = math.cos(self.theta_rad), math.sin(self.theta_rad)
        hits = []
        if c > 1e-9:
            hits.append((self.room_w_m - self.x_m) / c)
        elif c < -1e-9:
            hits.append(-self.x_m / c)
        if s > 1e-9:
            hits.append((self.room_h_m - self.y_m) / s)
        elif s < -1e-9:
            hits.append(-self.y_m / s)
        true_m = min(hits) - self.body_radius_m
        noisy_m = true_m + self.rng.normal(0.0, self.sonar_noise_m)
        return min(max(noisy_m, self.sonar_min_m), self.sonar_max_m)

    def _range_to_u16(self, range_m: float) -> int:
        volts = min(range_m * SONAR_V_PER_M, self.adc_vref)
        counts = round(volts / self.adc_vref * self.adc_max)
        # read_u16 scales an n-bit reading to 16 bits by repeating its top bits
        shift = 16 - self.adc_bits
        return (counts << shift) | (counts >> (self.adc_bits - shift))
