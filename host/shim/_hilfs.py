# The board's filesystem, as a MicroPython VFS mounted at / (docs/shim.md, "The board's
# filesystem"): a per-run copy of what `make flash` puts on the board, made by the host
# (host/rig/boardfs.py). Every path the firmware names (open, os.listdir, os.stat,
# os.remove, os.rename, os.mkdir, os.rmdir, os.statvfs, os.chdir, and import itself) is
# taken relative to the copy's root: ".." stops at /, as on a board, and nothing outside
# is reached. The flash has a size (the rig's [board] flash_size): writing past it raises
# OSError(ENOSPC) and os.statvfs counts the same blocks. The shim's own folder is seen,
# read-only and unlisted, at /_hil so that its modules still import.
_ENOSPC, _EROFS, _ENOTDIR = 28, 30, 20  # (MicroPython's errno names few of them)

_BLOCK = 4096  # a board filesystem's block (littlefs/FAT on 4 KiB flash sectors)
_DIR = 0x4000
_FILE = 0x8000


def _blocks(size):
    return (size + _BLOCK - 1) // _BLOCK


def _parts(path, cwd):
    """The path's components under the root, '.' and '..' resolved (never above the root)."""
    parts = [] if path.startswith("/") else [p for p in cwd.split("/") if p]
    for p in path.split("/"):
        if p == "..":
            if parts:
                parts.pop()
        elif p and p != ".":
            parts.append(p)
    return parts


SHIM = "_hil"  # where the shim's folder is seen


class _Folder:
    # a host folder seen as a board volume: paths mapped under `root`, /_hil under `shim`
    def __init__(self, host, root, shim):
        self._host = host  # the interpreter's own VfsPosix (the host's /), private to the shim
        self._root = root.rstrip("/")
        self._shim = shim.rstrip("/")
        self._cwd = "/"

    def _path(self, path):
        parts = _parts(path, self._cwd)
        if parts and parts[0] == SHIM:
            return "/".join([self._shim] + parts[1:])
        return "/".join([self._root] + parts) or "/"

    def _writable(self, path):
        parts = _parts(path, self._cwd)
        if parts and parts[0] == SHIM:
            raise OSError(_EROFS)
        return "/".join([self._root] + parts) or "/"

    def mount(self, readonly, mkfs):
        pass

    def umount(self):
        pass

    def chdir(self, path):
        parts = _parts(path, self._cwd)
        if not self._host.stat(self._path("/" + "/".join(parts)))[0] & _DIR:
            raise OSError(_ENOTDIR)
        self._cwd = "/" + "/".join(parts)

    def getcwd(self):
        return self._cwd

    def ilistdir(self, path):
        return self._host.ilistdir(self._path(path))

    def stat(self, path):
        return self._host.stat(self._path(path))


class _File:
    # a file open for writing: each write that grows it takes the flash's free blocks
    def __init__(self, fs, f, size, append):
        self._fs, self._f, self._size, self._append = fs, f, size, append

    def write(self, buf):
        end = (self._size if self._append else self._f.tell()) + len(buf)
        grow = _blocks(end) - _blocks(self._size) if end > self._size else 0
        if grow > self._fs.free_blocks():
            raise OSError(_ENOSPC)
        n = self._f.write(buf)
        if end > self._size:
            self._fs.used += grow
            self._size = end
        return n

    def __getattr__(self, name):  # read, readline, seek, tell, flush, close, readinto...
        return getattr(self._f, name)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self._f.close()

    def __iter__(self):
        return self

    def __next__(self):
        line = self._f.readline()
        if not line:
            raise StopIteration
        return line


class Board(_Folder):
    """The board's flash: a host folder with a size in blocks."""

    def __init__(self, host, root, shim, flash_bytes):
        super().__init__(host, root, shim)
        self.total = flash_bytes // _BLOCK
        self.used = self._count(self._root)

    def _count(self, folder):
        n = 0
        for entry in self._host.ilistdir(folder):
            path = folder + "/" + entry[0]
            if entry[1] == _DIR:
                n += 1 + self._count(path)
            else:
                n += _blocks(self._host.stat(path)[6])
        return n

    def free_blocks(self):
        return max(0, self.total - self.used)

    def _size(self, host_path):
        try:
            st = self._host.stat(host_path)
        except OSError:
            return None
        return st[6] if st[0] & _FILE else None

    def open(self, path, mode):
        if "r" in mode and "+" not in mode:
            return self._host.open(self._path(path), mode)
        host_path = self._writable(path)
        size = self._size(host_path)
        if size is None and self.free_blocks() < 1 and ("w" in mode or "a" in mode or "x" in mode):
            raise OSError(_ENOSPC)
        f = self._host.open(host_path, mode)
        if "w" in mode and size:
            self.used -= _blocks(size)  # truncated
            size = 0
        return _File(self, f, size or 0, "a" in mode)

    def remove(self, path):
        host_path = self._writable(path)
        size = self._size(host_path)
        self._host.remove(host_path)
        if size:
            self.used -= _blocks(size)

    def rename(self, old, new):
        target = self._size(self._writable(new))
        self._host.rename(self._writable(old), self._writable(new))
        if target:
            self.used -= _blocks(target)

    def mkdir(self, path):
        if self.free_blocks() < 1:
            raise OSError(_ENOSPC)
        self._host.mkdir(self._writable(path))
        self.used += 1

    def rmdir(self, path):
        self._host.rmdir(self._writable(path))
        self.used -= 1

    def statvfs(self, path):
        free = self.free_blocks()
        return (_BLOCK, _BLOCK, self.total, free, free, 0, 0, 0, 0, 255)


def mount(root, flash_bytes, shim_dir):
    """Put the board's flash at / (the shim, read-only, at /_hil); / is the cwd."""
    import os

    import vfs

    host = vfs.VfsPosix()
    vfs.umount("/")
    vfs.mount(Board(host, root, shim_dir, flash_bytes), "/")
    os.chdir("/")
