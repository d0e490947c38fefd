"""Link faults: a transport that damages or stalls the bytes of the plant link at the
rates of a fault schedule (``link_corrupt``, ``link_stall`` in ``sim_plant/faults.py``;
``docs/campaigns.md``).

It wraps any transport (:class:`~host.link.transport.FdTransport`, a board's serial
port) and is put between a :class:`~host.link.channel.Channel` and its transport by
:func:`wrap`. A write is one frame; a read is what the far end wrote since the last one
(in lockstep, one frame). Each write or read is, in its direction, damaged with chance
``rate`` (one bit flipped in one byte) or held back ``stall_ms`` of wall time. Draws come
from a stream per fault, seeded from the run's seed and the fault's place in the schedule.
The codec detects the damage and the run ends with ``LinkDamaged``; a stall longer than
the watchdog ends it with ``FirmwareHung``. ``counts`` says what was done.
"""

import time

import numpy as np

TO_FIRMWARE, FROM_FIRMWARE = "to_firmware", "from_firmware"


class FaultyTransport:
    def __init__(self, inner, faults, seed: int):
        self.inner = inner
        self.faults = [f for f in faults if f.kind in ("link_corrupt", "link_stall")]
        self.rngs = {f.index: np.random.default_rng([int(seed) & 0xFFFFFFFF, 0x11AC, f.index]) for f in self.faults}
        self.counts = {"corrupted_to_firmware": 0, "corrupted_from_firmware": 0, "stalls": 0, "stalled_s": 0.0}

    def __getattr__(self, name):  # side fds, busy polling, side_closed: the inner transport's
        return getattr(self.inner, name)

    def write(self, data: bytes, timeout_s: float = 5.0) -> None:
        self.inner.write(self._apply(data, TO_FIRMWARE), timeout_s)

    def read_some(self, timeout_s: float) -> bytes:
        data = self.inner.read_some(timeout_s)
        return self._apply(data, FROM_FIRMWARE) if data else data

    def _apply(self, data: bytes, direction: str) -> bytes:
        for f in self.faults:
            if f.direction not in (direction, "both"):
                continue
            rng = self.rngs[f.index]
            if rng.random() >= f.rate:
                continue
            if f.kind == "link_stall":
                self.counts["stalls"] += 1
                self.counts["stalled_s"] += f.stall_ms / 1000
                time.sleep(f.stall_ms / 1000)
            elif data:
                data = flip_bit(data, int(rng.integers(0, len(data) * 8)))
                self.counts[f"corrupted_{direction}"] += 1
        return data


def flip_bit(data: bytes, bit: int) -> bytes:
    damaged = bytearray(data)
    damaged[bit // 8] ^= 1 << (bit % 8)
    return bytes(damaged)


def wrap(channel, faults, seed: int):
    """Put a :class:`FaultyTransport` under ``channel`` if ``faults`` has link faults;
    the channel, either way."""
    if any(f.kind in ("link_corrupt", "link_stall") for f in faults):
        channel.transport = FaultyTransport(channel.transport, faults, seed)
    return channel
