"""Part ``record_link``: the master at the other end of a UART that drains a robot's
record stream (seed 002 §3.4, :mod:`sim_plant.duct_link`): every ``poll_ms`` it sends
``R``, reads the ``D seq ...`` lines and the closing ``K overruns`` back, and counts
records, skipped sequence numbers and latencies; ``script`` lines (speeds, gains, an
e-stop) go out at their times."""

from dataclasses import dataclass

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.duct_link import RecordReader
from sim_plant.option_table import MAX_TEXT, TIME, Num, Row, Rows


@dataclass(frozen=True)
class Line:
    """One line of text to send: printable, without its newline, at most 200 characters."""

    def problem(self, value):
        if isinstance(value, str) and len(value) <= MAX_TEXT and value.isprintable():
            return None
        return f"expected a line of at most {MAX_TEXT} printable characters, got {value!r}"[:200]


class RecordLink(PartType):
    kind = "record_link"
    doc = "A master on a UART that polls a robot's record stream (R; D seq ... lines; K overruns) and sends lines."
    OPTIONS = (
        Opt("poll_ms", Num("milliseconds", 0, 1_000_000), 100, "an R every (0: never)"),
        Opt("baud", Num("bits per second", 300, 10_000_000, whole=True), 115200, "the line's speed"),
        Opt(
            "period_us",
            Num("microseconds", 1_000, 1_000_000_000, whole=True),
            50_000,
            "the robot's control period (the records' clock)",
        ),
        Opt("script", Rows(Row((TIME, Line()), "[t_s, line]"), 1000), [], "lines the master sends, at t_s each"),
    )
    SIGNALS = (Sig("uart", "in", "bytes", "the UART both ways: the robot's records in, the master's lines out"),)
    TRUTH = ("{name}_records", "{name}_skipped", "{name}_latency_max_us")
    VIEWS = (View("count", "the records the master read and the sequence numbers it missed", ("uart",), TRUTH),)

    def add(self, build: Build) -> None:
        o = self.options
        uart = f"{self.name}.uart"
        script = [(float(t_s) * 1000, line) for t_s, line in o["script"]]
        build.parts.append(
            RecordReader(
                tx=uart, rx=uart, poll_ms=o["poll_ms"], baud=o["baud"], script=script, period_ms=o["period_us"] / 1000
            )
        )
