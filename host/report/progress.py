"""Progress of a long mission: simulated time against the mission's length, on one line.

:class:`MissionProgress` is the ``progress(t_us, t_end_us)`` callback of a
:class:`host.rig.loop.rig.Rig`, called while ``run_until`` runs with the end of that run.
It stays quiet for short runs; on a terminal it rewrites one line in place, elsewhere (a
CI log) it writes a line now and then. Where the text goes is the caller's business: it
is given ``rewrite(text)`` and ``line(text)``.

A scenario that runs its mission in chunks (``run_for(60)`` until the firmware says it is
done) declares the mission's length, ``MissionProgress(..., mission_s=3600)`` or ``with
progress.mission(3600):``: percent, rate and time left are then the mission's, carried
across the chunks, and a log gets a line at each tenth of it. Without one, each run is a
mission of its own.
"""

import contextlib
import time

SHOW_AFTER_S = 1.0  # wall time before a run counts as long
LOG_EVERY_S = 15.0  # wall time between two lines when the output is not a terminal
LOG_STEP = 0.1  # a declared mission's log line at each tenth of it ...
LOG_MIN_S = 5.0  # ... at most one in this much wall time


def progress_text(
    label: str, t_us: int, t_end_us: int, wall_s: float, done_us: int | None = None, start_us: int = 0
) -> str:
    """``label: 12.0 / 60.0 s simulated (20%), 0.5 s wall, 24x real time``; ``done_us``
    is the virtual time run in ``wall_s`` (default ``t_us``), ``start_us`` where the
    mission began (its share counts from there)."""
    span_us = t_end_us - start_us
    share = min(max(t_us - start_us, 0) / span_us, 1.0) if span_us > 0 else 1.0
    done_us = t_us if done_us is None else done_us
    speed = done_us / 1e6 / wall_s if wall_s > 0 else 0.0
    rate = f", {speed:.0f}x real time" if speed > 0 else ""
    left = f", about {(t_end_us - t_us) / 1e6 / speed:.0f} s left" if speed > 0 and t_end_us > t_us else ""
    return (
        f"{label}: {t_us / 1e6:.1f} / {t_end_us / 1e6:.1f} s simulated ({share:.0%}), {wall_s:.1f} s wall{rate}{left}"
    )


class MissionProgress:
    def __init__(self, label: str, *, rewrite=None, line=None, clock=time.monotonic, mission_s: float | None = None):
        self.label = label
        self._rewrite = rewrite  # on a terminal: overwrite the current line
        self._line = line  # elsewhere: write a whole line
        self._clock = clock
        self._t0 = None
        self._t0_us = 0
        self._next_line = 0.0
        self._last_line = 0.0
        self._next_share = LOG_STEP
        self._ended = False  # the end line of this mission is written
        self._mission_us = None if mission_s is None else round(mission_s * 1e6)
        self._start_us = None  # where the declared mission began: the first call after it
        self.shown = False

    @property
    def on_screen(self) -> bool:
        """A line rewritten in place is showing: the caller clears it when done."""
        return self.shown and self._rewrite is not None

    @contextlib.contextmanager
    def mission(self, seconds: float):
        """Runs inside make one mission of ``seconds`` simulated s, from the next call on."""
        self._mission_us, self._start_us, self._t0 = round(seconds * 1e6), None, None
        try:
            yield self
        finally:
            self._mission_us, self._start_us, self._t0 = None, None, None

    def __call__(self, t_us: int, t_end_us: int) -> None:
        now = self._clock()
        if self._t0 is None:
            self._t0, self._t0_us, self._last_line = now, t_us, now
            self._next_line, self._next_share, self._ended = now + LOG_EVERY_S, LOG_STEP, False
        start_us, end_us = 0, t_end_us
        if self._mission_us is not None:
            self._start_us = t_us if self._start_us is None else self._start_us
            start_us, end_us = self._start_us, self._start_us + self._mission_us
        wall_s = now - self._t0
        if wall_s < SHOW_AFTER_S:
            return
        text = progress_text(self.label, t_us, end_us, wall_s, t_us - self._t0_us, start_us)
        if self._rewrite is not None:
            self._rewrite(text)
            self.shown = True
        elif self._line is not None and self._log_due(now, t_us, start_us, end_us):
            self._line(text)
            self._next_line, self._last_line = now + LOG_EVERY_S, now
            self.shown = True
        if t_us >= t_end_us and self._mission_us is None:
            self._t0 = None  # the next run_until() starts a new mission

    def _log_due(self, now: float, t_us: int, start_us: int, end_us: int) -> bool:
        """A log's line: every LOG_EVERY_S, at each tenth of a declared mission (at most
        one in LOG_MIN_S), and once at the end of a mission that wrote one."""
        if t_us >= end_us and not self._ended:
            self._ended = True
            return self.shown
        share = (t_us - start_us) / (end_us - start_us) if end_us > start_us else 1.0
        tenth = self._mission_us is not None and share >= self._next_share and now - self._last_line >= LOG_MIN_S
        if tenth or now >= self._next_line:
            while self._next_share <= share:
                self._next_share += LOG_STEP
            return True
        return False
