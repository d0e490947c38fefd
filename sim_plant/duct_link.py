"""The master at the other end of seed 002's record link (§3.4): it asks the robot for its
buffered records every ``poll_ms`` ("R"), reads the batch back and checks it. The seed's
master (a Gumstix) polled over I2C; here it is a UART, the bytes timed at ``baud``.

The robot's record lines are ``D seq speedL speedR sonarF sonarL sonarR``, each batch
closed by ``K overruns`` (docs/duct.md). The reader counts the records, the sequence
numbers skipped (records the robot's ring overwrote before they were read), the robot's
own overrun count, and each record's latency: from the end of the control period that
made it (record ``seq`` is made at ``first_us + seq * period``, ``first_us`` taken from
the earliest record seen) to the end of the line that carried it.

``script`` is a list of ``(t_ms, line)`` the master sends at those times (speeds, gain,
e-stop: the seed's "speed and directional information", "emergency stop commands").
"""

from sim_plant.engine import Part
from sim_plant.plant import NEVER_US, Change

BITS_PER_BYTE = 10


class RecordReader(Part):
    FIXED_STATE = ("inputs", "outputs", "script")

    def __init__(self, *, tx="link.uart", rx="link.uart", poll_ms=100, baud=115200, script=(), period_ms=50):
        self.tx, self.rx = tx, rx
        self.inputs = {tx: "bytes"}
        self.outputs = {rx: "bytes"}
        self.poll_us = int(poll_ms * 1000) if poll_ms else 0
        self.byte_us = BITS_PER_BYTE * 1e6 / baud
        self.period_us = round(period_ms * 1000)
        self.script = sorted((int(t * 1000), str(line)) for t, line in script)
        self.next_script = 0
        self.next_poll_us = self.poll_us or NEVER_US
        self.next_us = min(self.next_poll_us, self.script[0][0] if self.script else NEVER_US)
        self.line_free_us = 0
        self.partial = ""
        self.records = 0
        self.batches = 0
        self.last_seq = -1
        self.skipped = 0
        self.overruns = 0
        self.first_seq_us = None  # made-time of seq 0, from the earliest record
        self.latencies_us: list[int] = []
        self.values: list[tuple] = []  # (seq, speedL, speedR, f, l, r)
        self.bad_lines = 0

    def initial_outputs(self) -> dict:
        return {self.rx: b""}  # a UART line: no level, only the bytes sent on it

    def fire(self, t_us: int, plant, out: list) -> None:
        while self.next_script < len(self.script) and self.script[self.next_script][0] <= t_us:
            out.append(Change(t_us, self.rx, (self.script[self.next_script][1] + "\n").encode()))
            self.next_script += 1
        if self.next_poll_us <= t_us:
            out.append(Change(t_us, self.rx, b"R\n"))
            self.next_poll_us = t_us + self.poll_us
        upcoming = self.script[self.next_script][0] if self.next_script < len(self.script) else NEVER_US
        self.next_us = min(self.next_poll_us, upcoming)

    def set_input(self, name: str, value, t_us: int, plant) -> bool:
        """Bytes the robot wrote at ``t_us``: each arrives when its stop bit ends, after
        what is already on the line."""
        data = bytes(value).decode(errors="replace")
        start = max(t_us, self.line_free_us)
        for i, ch in enumerate(data):
            if ch == "\n":
                self._line(self.partial, start + round((i + 1) * self.byte_us))
                self.partial = ""
            else:
                self.partial += ch
        self.line_free_us = start + round(len(data) * self.byte_us)
        return False

    def _line(self, line: str, t_us: int) -> None:
        parts = line.split()
        if parts[:1] == ["K"] and len(parts) == 2:
            self.batches += 1
            self.overruns = int(parts[1])
            return
        if parts[:1] != ["D"] or len(parts) != 7:
            self.bad_lines += 1
            return
        seq, *vals = (int(p) for p in parts[1:])
        if seq > self.last_seq + 1:
            self.skipped += seq - self.last_seq - 1
        self.last_seq = max(self.last_seq, seq)
        self.records += 1
        self.values.append((seq, *vals))
        made = t_us - seq * self.period_us  # the made-time of seq 0, plus this latency
        if self.first_seq_us is None or made < self.first_seq_us:
            self.first_seq_us = made
        self.latencies_us.append(made)

    def truth(self, t_us: int, plant) -> dict:
        lat = [v - self.first_seq_us for v in self.latencies_us] if self.latencies_us else [0]
        key = self.rx.split(".")[0]  # link.uart: link_records, ...
        return {
            f"{key}_records": self.records,
            f"{key}_skipped": self.skipped,
            f"{key}_overruns": self.overruns,
            f"{key}_batches": self.batches,
            f"{key}_latency_max_us": max(lat),
            f"{key}_bad_lines": self.bad_lines,
        }
