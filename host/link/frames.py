"""The frame codec and message layouts, as the host imports them.

One file serves both ends: ``host/shim/_hilframe.py`` runs inside MicroPython as the
shim's codec and is imported here unchanged, so the host and the shim cannot disagree
on a byte. The host's hottest read (an OUT per actuator write) uses a compiled form of
the same layout; ``host/tests/test_codec.py`` holds it to the codec's own on every vector.
"""

import struct as _struct

from host.shim import _hilframe as codec
from host.shim._hilframe import *  # noqa: F403  (the codec's names are this module's)

unpack_out = _struct.Struct(codec.OUT_FMT).unpack_from  # (t_us, handle, attr, value), as codec.unpack_out
