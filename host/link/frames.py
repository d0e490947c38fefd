"""The frame codec and message layouts, as the host imports them.

One file serves both ends: ``host/shim/_hilframe.py`` runs inside MicroPython as the
shim's codec and is imported here unchanged, so the host and the shim cannot disagree
on a byte. For the host's hot paths (an OUT per actuator write, a STATE per wake) this
module swaps in compiled forms of the same helpers, built from the same layouts;
``host/tests/test_codec.py`` holds them to the codec's own on every vector.
"""

import struct as _struct

from host.shim import _hilframe as codec
from host.shim._hilframe import *  # noqa: F403  (the codec's names are this module's)

_OUT = _struct.Struct(codec.OUT_FMT)
_STATE = _struct.Struct(codec.STATE_FMT)
_CHANGE = _struct.Struct(codec.CHANGE_FMT)

unpack_out = _OUT.unpack_from  # (t_us, handle, attr, value), as codec.unpack_out


def pack_state(base_us, t_end_us, horizon_us, changes):
    """codec.pack_state with compiled layouts."""
    pack = _CHANGE.pack
    parts = [_STATE.pack(base_us, t_end_us, horizon_us, len(changes))]
    for t, h, kind, value, extra in changes:
        dt = t - base_us if t > base_us else 0
        if kind == codec.CH_BYTES:
            parts.append(pack(dt, h, kind, value, 0) + extra)
        else:
            parts.append(pack(dt, h, kind, value, extra))
    return b"".join(parts)
