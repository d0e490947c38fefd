"""The frame codec and message layouts, as the host imports them.

One file serves both ends: ``host/shim/_hilframe.py`` runs inside MicroPython as the
shim's codec and is imported here unchanged, so the host and the shim cannot disagree
on a byte. The host's hottest read (an OUT per actuator write) uses a compiled form of
the same layout; ``host/tests/test_codec.py`` holds it to the codec's own on every vector.

The codec names every code on the wire (message types, CFG kinds, a pin's modes and
pulls, IRQ triggers, OUT attributes, STATE change kinds). The plant's signal kinds, which
never cross the link and which the shim has no use for, are named here, beside them:
the shim's heap (a board's RAM, ``heap_size``) holds no strings it never reads.
"""

import struct as _struct

from host.shim import _hilframe as codec
from host.shim._hilframe import *  # noqa: F403  (the codec's names are this module's)

unpack_out = _struct.Struct(codec.OUT_FMT).unpack_from  # (t_us, handle, attr, value), as codec.unpack_out


def unpack_cpu(p) -> tuple:
    """A CPU message (MCU time, docs/mcu-time.md): (t_us, compute_us, piece_us, the code's
    text). (Host-side only: the shim packs it inline, _hil._cpu_stretch.)"""
    return _struct.unpack_from(codec.CPU_FMT, p, 0) + (bytes(p[codec.CPU_LEN :]).decode("utf-8", "replace"),)


unpack_cpu_irq = _struct.Struct(codec.CPU_IRQ_FMT).unpack_from  # (t_from_us, t_us, the callbacks' compute_us)


# plant signal kinds: what a plant signal carries (``plant.inputs`` / ``plant.outputs``)
SIG_LEVEL = "level"  # 0/1
SIG_U16 = "u16"  # an ADC's reading, 0..65535
SIG_DUTY = "duty"  # a PWM duty, 0..65535
SIG_PWM = "pwm"  # a PWM waveform: duty and frequency (``plant.set_pwm``)
SIG_BYTES = "bytes"  # bytes, as a whole
SIG_UART = "uart"  # bytes timed on the line at the baud rate (``plant.send_bytes``)


def merge_edges(segments, changes) -> list:
    """The changes a STATE and its EDGES give the firmware, in the order it takes them, as
    the shim merges them (``_hil._apply_state``; ``_hilfast.apply_state`` the same in C): the
    segments' edges (``expand_edges``) and the STATE's changes in time order, at one instant
    the edges first. (Host-side only: the trace records these.)"""
    merged = codec.expand_edges(segments)
    i = 0
    for c in changes:  # (stable: the edges of an instant before its changes)
        while i < len(merged) and merged[i][0] <= c[0]:
            i += 1
        merged.insert(i, c)
        i += 1
    return merged
