# sys as the board's firmware sees it: the unix port's sys, with the board's
# sys.platform and sys.implementation._machine (firmware picks pins by them). Installed
# in sys.modules by _hil.start when the host names the board; `import sys` then finds it.
import sys as _sys
from collections import namedtuple

_Implementation = namedtuple("implementation", ("name", "version", "_machine", "_mpy", "_build"))


class _BoardSys:
    pass


def install(platform, machine):
    board = _BoardSys()
    for name in dir(_sys):
        if not name.startswith("__"):
            setattr(board, name, getattr(_sys, name))
    impl = _sys.implementation
    board.platform = platform
    board.implementation = _Implementation(
        impl.name, impl.version, machine, getattr(impl, "_mpy", 0), getattr(impl, "_build", "")
    )
    _sys.modules["sys"] = board
