# The record stream and the commands on a UART, as the seed's master/slave link (§3.4:
# the Gumstix asked the Roboaudiostix for the buffered data, a read drained the buffer,
# a flag said it was empty; commands set the wheels' speed and direction or stopped the
# robot). The seed gives no format; this one is lines of ASCII:
#
#   master -> robot   "R"          send every buffered record, oldest first
#                     "S <l> <r>"  manual: set speeds (ticks per period, signed)
#                     "E"          emergency stop (speeds 0 until "A")
#                     "A"          back to autonomous
#                     "K <kp100>"  the speed loops' gain x 100 (the seed's Kp sweep)
#                     "O <o> <f>"  options: 90-degree override, positional fix (0/1)
#   robot -> master   "D <seq> <speedL> <speedR> <sonarF> <sonarL> <sonarR>"
#                     "K <overruns>"  the buffer is empty, the transfer complete

RING = 32  # records: 1.6 s of control periods


class RecordRing:
    """A ring of records {seq, speedL, speedR, sonarF, sonarL, sonarR}; when full, a new
    record overwrites the oldest and counts an overrun."""

    def __init__(self, size=RING):
        self.size = size
        self.buf = [None] * size
        self.head = 0  # next slot to write
        self.count = 0
        self.seq = 0
        self.overruns = 0

    def push(self, speed_l, speed_r, f, left, right):
        self.buf[self.head] = (self.seq, speed_l, speed_r, f, left, right)
        self.seq += 1
        self.head = (self.head + 1) % self.size
        if self.count == self.size:
            self.overruns += 1
        else:
            self.count += 1

    def drain(self):
        """Every record, oldest first; the ring is empty afterwards."""
        n, start = self.count, (self.head - self.count) % self.size
        out = [self.buf[(start + i) % self.size] for i in range(n)]
        self.count = 0
        return out


def parse_command(line):
    """("R",), ("E",), ("A",), ("S", l, r), ("K", kp100), ("O", o, f); None for anything else."""
    parts = line.split()
    if not parts:
        return None
    op = parts[0]
    if op in ("R", "E", "A") and len(parts) == 1:
        return (op,)
    sizes = {"S": 3, "K": 2, "O": 3}
    if sizes.get(op) == len(parts):
        try:
            return (op,) + tuple(int(p) for p in parts[1:])
        except ValueError:
            return None
    return None


def format_batch(records, overruns):
    lines = ["D %d %d %d %d %d %d\n" % r for r in records]
    lines.append("K %d\n" % overruns)
    return "".join(lines)
