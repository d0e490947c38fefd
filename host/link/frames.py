"""The frame codec and message layouts, as the host imports them.

One file serves both ends: ``host/shim/_hilframe.py`` runs inside MicroPython as the
shim's codec and is imported here unchanged, so the host and the shim cannot disagree
on a byte. The host adds compiled :class:`struct.Struct` objects for its hot paths.
"""

from host.shim._hilframe import *  # noqa: F403  (the codec's names are this module's)
