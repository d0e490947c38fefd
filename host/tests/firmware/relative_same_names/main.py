# Four packages, each with a module named util (and p2 with a funcs, as asyncio has), one
# more under lib/: every relative import goes to its own package, at import time, at call
# time, from a nested package (`from .. import`), and from asyncio's lazy names.
import asyncio  # noqa: F401
import machine  # noqa: F401

import libpkg
import p1
import p2
import p3
import p4

packages = (p1, p2, p3, p4)
print("R utils", repr([p.util.VALUE for p in packages]))
print("R names", repr([p.VALUE for p in packages]))
print("R late", repr([p.late() for p in packages]))
print("R nested", repr((p1.sub.UP, p1.sub.OWN, p1.sub.LEAF, p1.Y)))
print("R lib", repr((libpkg.util.VALUE, libpkg.late())))
print("R lazy", repr(p2.LAZY if isinstance(p2.LAZY, str) else "asyncio"))
print("R cross", repr(p3.OTHER))
try:
    from . import util  # noqa: F401
except ImportError as e:
    print("R main", repr(str(e)))
