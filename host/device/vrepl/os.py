# os for the virtual board: the unix port's own, except that "" names the board's
# root folder (the current directory), as it does on a board's VFS. mpremote stats ""
# when copying to ":".
import sys

_path = sys.path
sys.path = []
from os import *  # noqa: E402,F403  the built-in, under this shadowing module
from os import stat as _stat  # noqa: E402

sys.path = _path
del _path


def stat(path):
    return _stat(path or ".")
