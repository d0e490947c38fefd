"""Progress of a long mission: simulated time against the mission's length, on one line.

:class:`MissionProgress` is the ``progress(t_us, t_end_us)`` callback of a
:class:`host.rig.rig.Rig`. It stays quiet for short runs; on a terminal it rewrites
one line in place, elsewhere (a CI log) it writes a line now and then. Where the text
goes is the caller's business: it is given ``rewrite(text)`` and ``line(text)``.
"""

import time

SHOW_AFTER_S = 1.0  # wall time before a run counts as long
LOG_EVERY_S = 15.0  # wall time between two lines when the output is not a terminal


def progress_text(label: str, t_us: int, t_end_us: int, wall_s: float, done_us: int | None = None) -> str:
    """``label: 12.0 / 60.0 s simulated (20%), 0.5 s wall, 24x real time``; ``done_us``
    is the virtual time run in ``wall_s`` (default ``t_us``)."""
    share = min(t_us / t_end_us, 1.0) if t_end_us > 0 else 1.0
    done_us = t_us if done_us is None else done_us
    speed = done_us / 1e6 / wall_s if wall_s > 0 else 0.0
    rate = f", {speed:.0f}x real time" if speed > 0 else ""
    left = f", about {(t_end_us - t_us) / 1e6 / speed:.0f} s left" if speed > 0 and t_end_us > t_us else ""
    return (
        f"{label}: {t_us / 1e6:.1f} / {t_end_us / 1e6:.1f} s simulated ({share:.0%}), {wall_s:.1f} s wall{rate}{left}"
    )


class MissionProgress:
    def __init__(self, label: str, *, rewrite=None, line=None, clock=time.monotonic):
        self.label = label
        self._rewrite = rewrite  # on a terminal: overwrite the current line
        self._line = line  # elsewhere: write a whole line
        self._clock = clock
        self._t0 = None
        self._t0_us = 0
        self._next_line = 0.0
        self.shown = False

    @property
    def on_screen(self) -> bool:
        """A line rewritten in place is showing: the caller clears it when done."""
        return self.shown and self._rewrite is not None

    def __call__(self, t_us: int, t_end_us: int) -> None:
        now = self._clock()
        if self._t0 is None:
            self._t0, self._t0_us = now, t_us
            self._next_line = now + LOG_EVERY_S
        wall_s = now - self._t0
        if wall_s < SHOW_AFTER_S:
            return
        text = progress_text(self.label, t_us, t_end_us, wall_s, t_us - self._t0_us)
        if self._rewrite is not None:
            self._rewrite(text)
            self.shown = True
        elif self._line is not None and (now >= self._next_line or (self.shown and t_us >= t_end_us)):
            self._line(text)  # a log gets a line every LOG_EVERY_S, and the end of a mission that got one
            self._next_line = now + LOG_EVERY_S
            self.shown = True
        if t_us >= t_end_us:
            self._t0 = None  # the next run_until() starts a new mission
