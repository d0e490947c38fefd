"""A poll that can never end, named (``docs/reliability.md``, "A poll that never ends").

A driver that waits on a chip polls a register until a bit changes (a BOOT bit to clear, a
data-ready bit to set). When the chip never changes it (a part left powered down, a bit
the model does not honour), the firmware spins in virtual time with nothing on its
console. :class:`PollWatch` counts, per (bus, address, register), the reads in a row that
gave the same answer; once :data:`POLL_READS` of them span :data:`POLL_SPAN_US` of virtual
time, it names the poll once: bus, address, register, the answer, since when, and what
the chip's model honours there. A count and a comparison a read: cheap on every transfer.

The firmware's stack is the shim's, not the host's: a note gives the virtual time and the
register instead (the console's tail and ``trace.jsonl`` show what came before).
"""

POLL_READS = 10_000
"""Reads in a row with the same answer ..."""
POLL_SPAN_US = 1_000_000
"""... over at least this much virtual time: a poll that is not going to end."""


class PollWatch:
    def __init__(self, reads: int = POLL_READS, span_us: int = POLL_SPAN_US):
        self.reads = reads
        self.span_us = span_us
        self.runs = {}  # (bus, address, register) -> [answer, since t_us, reads in a row]
        self.named = set()  # the keys named already (once each)

    def seen(self, t_us: int, bus: str, address, register, answer: bytes) -> tuple | None:
        """A read's answer; (since t_us, reads) when it completes a poll to name, else None."""
        key = (bus, address, register)
        run = self.runs.get(key)
        if run is None or run[0] != answer:
            self.runs[key] = [answer, t_us, 1]
            return None
        run[2] += 1
        if run[2] >= self.reads and t_us - run[1] >= self.span_us and key not in self.named:
            self.named.add(key)
            return run[1], run[2]
        return None


def poll_text(t_us: int, bus: str, address, register, answer: bytes, since_us: int, reads: int, device) -> str:
    """The note for a poll that never ends, with what the chip's model honours."""
    at = f"0x{address:02x}" if address is not None else "(chip select)"
    reg = f"register 0x{register:02x}" if register is not None else "no register"
    shown = " ".join(f"{b:02x}" for b in answer[:8]) or "nothing"
    text = (
        f"a poll that never ends? the firmware read {bus} {at} {reg} {reads} times from virtual "
        f"t={since_us / 1e6:.6f} s to t={t_us / 1e6:.6f} s and got {shown} each time"
    )
    if device is None:
        return text if address is None else text + " (no chip of the plant answers there)"
    modelled = getattr(device, "MODELLED", None)
    if modelled is None:
        return text + f" ({device.label}: a {type(device).__name__}, not a register chip)"
    here = modelled.get(register)
    what = f"the model honours {here}" if here else "the model keeps it as plain memory: only a write changes it"
    return text + f"; {device.where()}: {what} (all it honours: {device.modelled_text()})"
