# os for the virtual board: the unix port's own, except that "" names the board's
# root folder (the current directory), as it does on a board's VFS. mpremote stats ""
# when copying to ":".
import sys

_path = sys.path
sys.path = []
from os import *  # noqa: E402,F403  the built-in, under this shadowing module
from os import ilistdir as _ilistdir  # noqa: E402
from os import stat as _stat  # noqa: E402

sys.path = _path
del _path


def stat(path):
    return _stat(path or ".")


def ilistdir(path=""):
    # a board's VFS (FAT, littlefs) gives (name, type, inode, size); the unix port's
    # gives three fields, and mpremote's `ls` shows a size of 0 without the fourth
    folder = path or "."
    for entry in _ilistdir(folder):
        size = _stat(folder + "/" + entry[0])[6] if entry[1] == 0x8000 else 0
        yield (entry[0], entry[1], entry[2], size)


def listdir(path=""):
    return [entry[0] for entry in ilistdir(path)]
