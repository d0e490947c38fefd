# Two packages whose __init__ imports its own helper relatively (`from . import helper`),
# with asyncio (a frozen package) and machine loaded: each finds its own.
import asyncio  # noqa: F401
import machine  # noqa: F401

import pkg_a
import pkg_b

print("R a", repr(pkg_a.VALUE + pkg_a.helper.VALUE))
print("R b", repr(pkg_b.VALUE + pkg_b.helper.VALUE))
