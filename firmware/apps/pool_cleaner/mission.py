# The pool cleaner's mission (seeds 000/001): measure the width, then clean the pool
# lane by lane. Run_Straight runs while the last bumper touched is bumper1 (front),
# Run_Cross while it is bumper2 (rear): the machine's own logic reverses the tracks at
# each end wall, the firmware only stops one track at a time to steer. Straight runs
# hold a lane at a fixed distance d from the reference ("left") wall; cross runs follow
# an oblique path to the next lane, one LANE_M nearer that wall.
#
# Pure Python, driven once per 50 ms quantum by main.py with the time, the newest sonar
# depth and the bumpers; CPython tests drive it too. Departures from the C code of seed
# 000 (App. A) are marked "C:" where they are made; docs/pool_cleaner.md lists them.
import math

from kalman import DS_M, LaneFilter
from steering import MAX_STOP_MS, QUANTUM_MS, correction_ms, quantise, stop_for_turn_ms, stop_ms, turn_rad

try:
    from micropython import const
except ImportError:  # CPython

    def const(x):
        return x


SPEED_M_S = 0.3  # both tracks, forwards or backwards (B400 datasheet)
LANE_M = 0.4  # lane step, the code's WIDTH
DELAY_MS = const(4000)  # open loop after a reversal: the machine stops, floats, restarts
LEAVE_WALL_MS = const(1000)  # straight runs: more open loop "to go away from the wall"
LEAD_IN_DIV = const(6)  # cross runs: open loop for L/6 "to avoid the reflection of the
# sonar beam on the perpendicular wall" (seed 000 §6.2.2)
SWITCH_SETTLE_MS = const(2000)  # open loop after a sonar switch (the code's delay(2000))
WIDTH_SAMPLES = const(10)  # start-up width: 10 readings (Take_start_ref)
MIN_RANGE_M = 3.0  # readings under 3 m are discarded (seed 001 §3; the code's MINTHRESHOLD)
GATE_M = 0.3  # a reading this far from the prediction is rejected (the code's TH_PAR) ...
GATE_AGREE = const(3)  # ... unless 3 in a row agree with each other: the machine is there
MEAN_KICK_RAD = -0.0174  # mean heading kick at each restart, the pump turning (MEANA)
MAX_HEADING_RAD = 0.1  # steering limit, 5.7 deg off the lane direction (see _steer)
MAX_TOTAL_STOP_MS = const(10000)  # net stop time per run (the code's MAXDELAY)
FINAL_REF_M = 0.0  # the last lane runs along the far wall
RAMP_SHARE = 0.85  # share of a cross run's closed-loop stretch spent on the oblique
SLOT_TIMEOUT_MS = const(550)  # no sentence this long after the last: a dead-reckoning slot
BLIND_RESTART = const(6)  # slots without a reading (3 s) after which the filter restarts
SWITCH_REPEAT_LAPS = const(1)  # "a few laps are repeated" after a sonar switch (seed 001 §7)
FIR_WEIGHTS = (0.4, 0.3, 0.2, 0.1)  # the code's Filtering(), newest reading first
LANE_LOG_SLOTS = const(2)  # a lane line every 2 closed-loop slots (1 s): an hour is ~130 kB
LANE_LOG_COLUMNS = "t_ms sonar depth_m d_m phi_rad ref_m stop_ms"

FRONT = const(1)  # bumper1
REAR = const(2)  # bumper2

START = const(0)  # tracks held, width measurement
TO_EDGE = const(1)  # tracks running, waiting for bumper1
STRAIGHT = const(2)
CROSS = const(3)
DONE = const(4)
PHASE_NAMES = ("start", "to-edge", "straight", "cross", "done")

NO_ECHO = -1.0


def hms(s):
    s = int(s)
    return "%d:%02d:%02d" % (s // 3600, s // 60 % 60, s % 60)


class Mission:
    def __init__(self, log=print):
        self.log = log
        self.filter = LaneFilter()
        self.phase = START
        self.stop_left = 1  # track-stop outputs; both held while measuring the width
        self.stop_right = 1
        self.sonar = 0  # 0: left sonar, d read directly; 1: right, d = width - reading
        self.latched = 0  # the last bumper touched (the code's Read_Bumper latch)
        self.width_m = 0.0  # start-up distance to the far wall, also sonar 1's conversion
        self.reference_m = 0.0  # the lane: distance to the reference wall
        self.target_m = 0.0  # where the current cross run goes
        self.ref_m = 0.0  # reference of this slot (ramps on a cross run)
        self.phi_ref_rad = 0.0
        self.alpha_rad = 0.0
        self.run_ms = 0  # duration of the last straight run, bumper to bumper
        self.runs = 0
        self.t_run0_ms = 0
        self.t_slot_ms = 0
        self.t_ramp0_ms = -1
        self.open_until_ms = 0
        self.ramp_ms = 0
        self.tracking = False  # the filter runs (closed loop)
        self.phi0_rad = MEAN_KICK_RAD
        self.last_stop_ms = 0
        self.queue_ms = 0  # feed-forward turn still to apply, signed
        self.total_ms = 0
        self.pulse_q = 0  # quanta left in the current stop pulse
        self.switch_pending = False
        self.switch_until_ms = -1
        self.repeat_laps = 0
        self.estimate_total_s = -1.0
        self.done_ms = -1
        self._acc_m = 0.0
        self._acc_n = 0
        self._fir = [0.0, 0.0, 0.0]  # the previous accepted readings, newest first
        self._fir_n = 0
        self._hist = [0.0] * WIDTH_SAMPLES  # last estimates after an update, a ring
        self._hist_n = 0
        self._reject_n = 0
        self._reject_last_m = 0.0
        self._blind = 0  # slots in a row without a reading
        self.slots = 0
        self.rejected = 0
        self.missing = 0
        self.repeats = 0
        self.restarts = 0

    # -- per quantum --------------------------------------------------------------

    def quantum(self, now_ms, depth, bumper):
        """One 50 ms step: depth is None (no new sentence), NO_ECHO or metres; bumper is
        FRONT, REAR or 0 (which one is pressed now)."""
        if self.pulse_q:
            self.pulse_q -= 1
            if not self.pulse_q:
                self.stop_left = self.stop_right = 0
        if bumper and bumper != self.latched:
            self.latched = bumper
            self._bumper(now_ms, bumper)
        if depth is not None:
            self._slot(now_ms, depth)
        elif self.phase in (STRAIGHT, CROSS) and now_ms - self.t_slot_ms >= SLOT_TIMEOUT_MS:
            self._slot(now_ms, None)  # the sounder is silent: go on by dead reckoning

    # -- runs ---------------------------------------------------------------------

    def _bumper(self, now_ms, bumper):
        if self.phase == TO_EDGE:
            if bumper == FRONT:
                self._begin(now_ms, STRAIGHT)
        elif self.phase == STRAIGHT and bumper == REAR:
            self.run_ms = now_ms - self.t_run0_ms
            self._estimate(now_ms)
            if self.reference_m <= FINAL_REF_M + 0.001:
                self._finish(now_ms)
            else:
                self._begin(now_ms, CROSS)
        elif self.phase == CROSS and bumper == FRONT:
            self._lane_test()
            self._begin(now_ms, STRAIGHT)

    def _begin(self, now_ms, phase):
        # prior of the path angle: the tracks reverse but the heading stays, so the last
        # run's angle changes sign; the pump's kick adds MEANA to the heading, which
        # bends the path the other way in the other travel direction. C: MEANA always
        kick = MEAN_KICK_RAD if phase == STRAIGHT else -MEAN_KICK_RAD
        self.phi0_rad = kick - (self.filter.phi_rad if self.tracking else 0.0)
        self.phase = phase
        self.runs += 1
        self.t_run0_ms = now_ms
        self.tracking = False
        self.pulse_q = 0
        self.stop_left = self.stop_right = 0  # a stop in progress ends: the machine reverses
        self.last_stop_ms = 0
        self.queue_ms = 0
        self.total_ms = 0
        self.ref_m = self.reference_m
        self.phi_ref_rad = 0.0
        self.t_ramp0_ms = -1
        self._reject_n = 0
        self._hist_n = 0
        self._fir_n = 0
        self._blind = 0
        if phase == STRAIGHT:
            open_ms = DELAY_MS + LEAVE_WALL_MS
            # C: switches when Average() < 3.0 at the start of a straight run, i.e. after a
            # cross run on readings under 3 m; with those discarded (seed 001) the next
            # lane must stay clear of 3 m by the noise (GATE_M), else the filter only sees
            # the readings above 3 m and drifts: the switch comes a lane earlier
            self.switch_pending = self.sonar == 0 and self.reference_m - LANE_M < MIN_RANGE_M + GATE_M
        else:
            open_ms = DELAY_MS + (self.run_ms - DELAY_MS) // LEAD_IN_DIV  # L = (run - DELAY) v
            if self.repeat_laps:
                self.repeat_laps -= 1
                self.target_m = self.reference_m
                self.repeats += 1
                self.log("cross: repeating lane %.2f m after the sonar switch" % self.reference_m)
            else:
                self.target_m = max(self.reference_m - LANE_M, FINAL_REF_M)
            # the oblique takes most of the closed-loop stretch and ends before the far
            # wall, so the machine settles on the lane. C: alpha = atan2(WIDTH, 5L/6), a
            # ramp ending at the wall
            self.ramp_ms = int((self.run_ms - open_ms) * RAMP_SHARE)
        self.open_until_ms = now_ms + open_ms
        self.log(
            "%s %d: lane %.2f m, sonar %d, t %s"
            % (PHASE_NAMES[phase], self.runs, self.reference_m, self.sonar, hms(now_ms // 1000))
        )

    def _lane_test(self):
        """The code's test: if 0 < Average() - ref < WIDTH (the machine ended between the
        new lane and the old one) take the new lane, else repeat the old one. Here an
        overshoot of up to half a lane past the new lane is taken too: the run's
        estimate scatters about the lane it ends on."""
        if self.target_m == self.reference_m:
            return
        d_m = self.average_m()
        if -LANE_M / 2 < d_m - self.target_m < LANE_M:
            self.reference_m = self.target_m
        else:
            self.repeats += 1
            self.log("cross: ended at %.2f m, not on lane %.2f m: repeating the same path" % (d_m, self.target_m))

    def average_m(self):
        """Mean of the last 10 estimates after a measurement (the code's Average(), over
        the 10-value FIFO it meant to keep: its forward shift filled it with copies)."""
        n = min(self._hist_n, WIDTH_SAMPLES)
        return sum(self._hist[:n]) / n if n else self.filter.d_m

    def _estimate(self, now_ms):
        """Time to finish: two runs per lane left (the code's timetogo, with the run timed
        bumper to bumper in ms rather than from DELAY after it in whole seconds)."""
        to_go_s = 2 * self.run_ms / 1000 * (self.reference_m / LANE_M)
        if self.estimate_total_s < 0:
            self.estimate_total_s = now_ms / 1000 + to_go_s
            self.log(
                "estimate: runs of %.1f s, %.2f m to clean: cleaning time %s"
                % (self.run_ms / 1000, self.reference_m, hms(self.estimate_total_s))
            )
        self.log("time to finish %s" % hms(to_go_s))

    def _finish(self, now_ms):
        self.phase = DONE
        self.done_ms = now_ms
        self.pulse_q = 0
        self.stop_left = self.stop_right = 1  # both tracks stopped: the code's `stop` word
        self.log(
            "done: pool cleaned in %s (estimate %s), %d runs, %d repeated, %d readings rejected, %d missing"
            % (hms(now_ms // 1000), hms(self.estimate_total_s), self.runs, self.repeats, self.rejected, self.missing)
        )

    # -- sonar slots --------------------------------------------------------------

    def _slot(self, now_ms, depth):
        dt_ms = now_ms - self.t_slot_ms
        self.t_slot_ms = now_ms
        raw = depth if depth is not None and depth >= MIN_RANGE_M else None
        if self.phase == START:
            self._measure_width(raw)
            return
        if self.phase not in (STRAIGHT, CROSS):
            return
        if now_ms < self.open_until_ms:
            return  # open loop: reversal, leaving the wall, cross lead-in
        self.slots += 1
        if raw is None:
            self.missing += 1
            self._blind += 1
        d = None if raw is None else (raw if self.sonar == 0 else self.width_m - raw)
        f = self.filter
        if self.tracking:
            f.predict(turn_rad(self.last_stop_ms), DS_M * dt_ms / 500)
        else:  # first closed-loop sample of the run
            f.start(self.ref_m, self.phi0_rad, d)
            self.tracking = True
            self._plan_oblique(now_ms)
            d = None
        self.last_stop_ms = 0
        if self._switching(now_ms):
            return
        if d is not None:
            self._update(d)
        self._follow_oblique(now_ms)
        self._steer()
        if self.slots % LANE_LOG_SLOTS == 0:
            self._lane_line(now_ms, depth)

    def _lane_line(self, now_ms, depth):
        """The filter's state for the console, one line a second: what the machine
        believes (the sounder's depth, -1 for none; the estimate of d and phi; the lane
        it holds; the stop it just commanded), LANE_LOG_COLUMNS, to plot against truth."""
        f = self.filter
        self.log(
            "lane %d %d %.2f %.3f %.4f %.3f %d"
            % (now_ms, self.sonar, -1.0 if depth is None else depth, f.d_m, f.phi_rad, self.ref_m, self.last_stop_ms)
        )

    def _measure_width(self, raw):
        """Start-up: 10 readings of the left sonar with both tracks held (the code's
        Take_start_ref); from the corner, the distance to the far wall is the first lane."""
        if raw is None:
            return
        self._acc_m += raw
        self._acc_n += 1
        if self._acc_n == WIDTH_SAMPLES:
            self.width_m = self._acc_m / WIDTH_SAMPLES
            self.reference_m = self.width_m
            self.phase = TO_EDGE
            self.stop_left = self.stop_right = 0
            self.log("width %.2f m: first lane, waiting for bumper1" % self.width_m)
            self.log("lane columns: " + LANE_LOG_COLUMNS)

    def _update(self, d):
        """Measurement update. Gated against the prediction (the code's TH_PAR test, which
        compared with a buffer its forward shift had filled with copies of one value),
        then the code's FIR, 0.4 0.3 0.2 0.1, over the accepted readings. After a dropout
        the filter restarts from its prediction, as after a reversal: its gain schedule
        (the seed's) assumes a reading every slot, and would take the drift of the blind
        stretch for a heading error."""
        f = self.filter
        blind, self._blind = self._blind, 0
        if blind >= BLIND_RESTART:
            f.start(f.d_m, f.phi_rad, d)
            self._fir_n = 0
            self._hist_n = 0
            self._reject_n = 0
            self.restarts += 1
            self.log("filter: readings back after %d slots, restarted at %.2f m" % (blind, f.d_m))
            return
        if abs(f.innovation(d)) > GATE_M:
            self._reject(d)
            return
        self._reject_n = 0
        fir = self._fir
        if not self._fir_n:
            fir[0] = fir[1] = fir[2] = d
        self._fir_n += 1
        w = FIR_WEIGHTS
        z = w[0] * d + w[1] * fir[0] + w[2] * fir[1] + w[3] * fir[2]
        fir[2] = fir[1]
        fir[1] = fir[0]
        fir[0] = d
        f.update(z)
        self._hist[self._hist_n % WIDTH_SAMPLES] = f.d_m
        self._hist_n += 1

    def _reject(self, d):
        self.rejected += 1
        if self._reject_n and abs(d - self._reject_last_m) <= GATE_M:
            self._reject_n += 1
        else:
            self._reject_n = 1
        self._reject_last_m = d
        if self._reject_n >= GATE_AGREE:  # consistent readings: the machine really is there
            self.filter.d_m = d
            self._reject_n = 0
            self._hist_n = 0
            self._fir_n = 0
            self.restarts += 1
            self.log("filter: %d readings agree on %.2f m, taken" % (GATE_AGREE, d))

    def _switching(self, now_ms):
        """Sonar switch (the code's Check_Measure): select sonar 1 at the first
        closed-loop slot of the run, then 2 s of open loop while it settles; from then on
        d = width - reading. True while the switch runs."""
        if self.switch_pending:
            self.switch_pending = False
            self.sonar = 1
            self.switch_until_ms = now_ms + SWITCH_SETTLE_MS
            self.repeat_laps = SWITCH_REPEAT_LAPS
            self.log("sonar: switching to sonar 1 at %.2f m" % self.filter.d_m)
            return True
        if self.switch_until_ms < 0:
            return False
        if now_ms < self.switch_until_ms:
            return True
        self.switch_until_ms = -1
        return False

    # -- the oblique of a cross run -------------------------------------------------

    def _plan_oblique(self, now_ms):
        """First closed-loop slot of a cross run: alpha = atan(step / ramp length); turn
        by alpha (a left stop, from the inverse of eq. 7.1) and ramp the reference at
        SPEED sin(alpha) (Run_Cross's ref -= SPEED sin(alpha) per one-second iteration)."""
        if self.phase != CROSS or self.target_m >= self.reference_m or self.ramp_ms <= 0:
            return
        step_m = self.reference_m - self.target_m
        self.alpha_rad = math.atan2(step_m, SPEED_M_S * self.ramp_ms / 1000)
        self.t_ramp0_ms = now_ms
        self.phi_ref_rad = -self.alpha_rad  # C: 10 (delta - alpha), the sign reversed
        self.queue_ms -= quantise(stop_for_turn_ms(self.alpha_rad), 1 << 20)

    def _follow_oblique(self, now_ms):
        if self.t_ramp0_ms < 0:
            return
        ref = self.reference_m - SPEED_M_S * math.sin(self.alpha_rad) * (now_ms - self.t_ramp0_ms) / 1000
        if ref <= self.target_m:  # on the new lane: straighten up (the code's Stop_Right)
            ref = self.target_m
            self.t_ramp0_ms = -1
            self.phi_ref_rad = 0.0
            self.queue_ms += quantise(stop_for_turn_ms(self.alpha_rad), 1 << 20)
        self.ref_m = ref

    # -- steering -----------------------------------------------------------------

    def _steer(self):
        f = self.filter
        if self.pulse_q:  # a stop still running (a slot came early): let it end
            return
        if self.queue_ms:  # a feed-forward turn goes first, MAX_STOP_MS per slot
            stop = max(-MAX_STOP_MS, min(MAX_STOP_MS, self.queue_ms))
            self.queue_ms -= stop
        else:
            dphi = f.phi_rad - self.phi_ref_rad
            stop = stop_ms(correction_ms(f.d_m - self.ref_m, dphi))
            # the steering limit: no stop that turns further past MAX_HEADING_RAD. The seed's
            # 12 deg keeps the sonar within its usable 15 deg; but past the 9 deg beam's
            # half-width the echo comes off the beam's edge and reads long (d / cos(inc -
            # 4.5 deg)), which the filter takes for the machine drifting off: the loop then
            # turns further. 5.7 deg keeps that bias under a centimetre.
            if (stop < 0 and f.phi_rad < -MAX_HEADING_RAD) or (stop > 0 and f.phi_rad > MAX_HEADING_RAD):
                stop = 0
            total = self.total_ms + stop  # the code's MAXDELAY: net stop within +-10 s a run
            if (total > MAX_TOTAL_STOP_MS and f.phi_rad < 0) or (total < -MAX_TOTAL_STOP_MS and f.phi_rad > 0):
                self.total_ms = 0
            elif total > MAX_TOTAL_STOP_MS or total < -MAX_TOTAL_STOP_MS:
                stop = 0
        self.total_ms += stop
        self.last_stop_ms = stop
        if stop:
            self.pulse_q = abs(stop) // QUANTUM_MS
            self.stop_left = 1 if stop < 0 else 0
            self.stop_right = 1 if stop > 0 else 0
