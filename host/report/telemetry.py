"""What the firmware said it believed: its telemetry lines in ``console.log``, as arrays.

A firmware that wants its beliefs plotted prints a line now and then with a tag and
numbers, as a board developer prints to the USB serial port (``lane 123450 0 7.51 ...``);
the app's view names the tag and its columns. Whatever else is on the line before the
tag (a time stamp the harness adds, say) is ignored. The firmware's own clock is turned
into virtual time by the first toggle of its control probe, the moment its loop started
(``firmware_t0_us``).
"""

import re

import numpy as np

from host.artefacts.folder import CONSOLE, TraceData

NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|nan|inf"


def console_text(trace: TraceData) -> str:
    """The firmware's console as the trace folder holds it ('' without one)."""
    path = trace.folder / CONSOLE
    return path.read_text(encoding="utf-8", errors="replace") if path.is_file() else ""


def rows(text: str, tag: str, columns: tuple[str, ...]) -> dict[str, np.ndarray]:
    """Every line ``<tag> v1 v2 ...`` with one number per column, as a column -> array
    mapping (empty arrays when there is none). Lines with another count are skipped:
    a line cut short at the end of a run is no measurement."""
    pattern = re.compile(rf"(?:^|\s){re.escape(tag)}((?: (?:{NUMBER}))+)[ \t]*\r?$", re.MULTILINE)
    values = [m.group(1).split() for m in pattern.finditer(text)]
    table = np.asarray([v for v in values if len(v) == len(columns)], dtype=float).reshape(-1, len(columns))
    return {name: table[:, i] for i, name in enumerate(columns)}


def firmware_t0_us(trace: TraceData, probe: str = "probe:control") -> int:
    """Virtual time of the control probe's first change: when the firmware's loop took
    its time origin (0 without a probe)."""
    for t_us, name, _value in trace.events:
        if name == probe:
            return t_us
    return 0
