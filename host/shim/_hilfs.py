# The board's filesystem, as a MicroPython VFS mounted at / (docs/shim.md, "The board's
# filesystem"): a per-run copy of what `make flash` puts on the board, made by the host
# (host/rig/targets/boardfs.py). Every path the firmware names (open, os.listdir, os.stat,
# os.remove, os.rename, os.mkdir, os.rmdir, os.statvfs, os.chdir, and import itself) is
# taken relative to the copy's root: ".." stops at /, as on a board, and nothing outside
# is reached. The shim's own folder is seen, read-only and unlisted, at /_hil so that its
# modules still import.
#
# The flash has a size (the rig's [board] flash_size) and is counted as littlefs v2 counts
# it on the ESP32 and RP2040 ports (docs/shim.md, "The flash's size"):
# - blocks of 4096 bytes; MicroPython's VfsLfs2 gives littlefs cache_size = 4 * max(read_size,
#   prog_size) = 128 (extmod/vfs_lfsx.c, init_config; readsize = progsize = 32 by default),
#   and littlefs inlines a file of at most that many bytes into its directory's metadata
#   (lfs.c, inline_max = min(cache_size, attr_max, block_size / 8));
# - a bigger file takes the blocks of its CTZ skip-list: block n > 0 begins with ctz(n) + 1
#   pointers of 4 bytes (lfs.c, lfs_ctz_index); its size is its end, so a seek past the end
#   and a write count the gap as written blocks (a sparse file is as big on a flash);
# - each directory (the root too, with the superblock) is a metadata pair of 2 blocks, and
#   another pair for each half block of its entries (lfs.c, lfs_dir_splittingcompact splits a
#   pair past block_size / 2); an entry costs its create, name and struct tags (4 bytes each),
#   its name, and its inline data (a file) or 8 bytes (a CTZ head, a directory's pair);
# - a write, create or mkdir past the free blocks raises OSError(28) (ENOSPC) before it is
#   made; os.statvfs gives the tuple of vfs_lfsx.c's statvfs with the same blocks.
#
# Nothing reachable from the firmware holds the host: the interpreter's VfsPosix, the
# copy's host path, the count and the open host files live in the closure of _board's op
# (MicroPython has no __closure__), never in an attribute or a global; the mounted object
# and its files hold only that op, which does what a board's VFS does and no more (an open
# file gives its read methods, never its host file's write).
from io import IOBase as _IOBase

_ENOSPC, _EROFS, _ENOTDIR = 28, 30, 20  # (MicroPython's errno names few of them)

_BLOCK = 4096  # a board filesystem's block (littlefs on 4 KiB flash sectors)
_INLINE = 128  # littlefs's inline_max under MicroPython's VfsLfs2 (see above)
_HALF = _BLOCK // 2  # a metadata pair's entries before littlefs splits it
_TAG = 12  # create + name + struct tags of an entry
_ROOT = _TAG + 8 + 24  # the superblock's entry in the root pair ("littlefs", its 24 bytes)
_DIR = 0x4000
_FILE = 0x8000
SHIM = "_hil"  # where the shim's folder is seen
_READS = ("read", "readinto", "readline", "readlines", "seek", "tell", "flush")


def _popc(n):
    return bin(n).count("1")


def data_blocks(size):
    """Blocks of a file's data: none inline, else its CTZ skip-list's (lfs.c lfs_ctz_index)."""
    if size <= _INLINE:
        return 0
    b = _BLOCK - 8
    off = size - 1
    i = off // b
    if i:
        i = (off - 4 * (_popc(i - 1) + 2)) // b
    return i + 1


def entry_bytes(name, size=None):
    """An entry's bytes in its directory's metadata: a file of ``size``, or a directory (None)."""
    tail = 8 if size is None or size > _INLINE else size
    return _TAG + len(name) + tail


def pair_blocks(meta):
    """Blocks of a directory's metadata pairs for ``meta`` bytes of entries."""
    return 2 * max(1, (meta + _HALF - 1) // _HALF)


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


def mount(root, flash_bytes, shim_dir):
    """Put the board's flash at / (the shim, read-only, at /_hil); / is the cwd."""
    import os

    import vfs

    vfs.umount("/")
    vfs.mount(_board(vfs.VfsPosix(), root.rstrip("/"), shim_dir.rstrip("/"), flash_bytes), "/")
    os.chdir("/")


# The count's state, [meta, used, total]: meta maps a board folder ("" is /) to the bytes of
# its entries, used and total are blocks. It lives in _board's closures only; these
# functions are handed it (and the host, when they need it), never keep it.


def _split(board):
    folder, _, name = board.rpartition("/")
    return folder, name


def _change(st, folder, dmeta, ddata, new_folder=None):
    # take (or give back) dmeta bytes of folder's metadata and ddata blocks; ENOSPC, nothing
    # changed, when the flash has not the blocks
    meta = st[0]
    before = meta.get(folder, 0)
    after = before + dmeta
    grow = pair_blocks(after) - pair_blocks(before) + ddata
    if new_folder is not None:
        grow += pair_blocks(0)
    if grow > 0 and grow > st[2] - st[1]:
        raise OSError(_ENOSPC)
    meta[folder] = after
    if new_folder is not None:
        meta[new_folder] = 0
    st[1] += grow


def _resize(st, board, old, new):
    # a file's size from old (None: new) to new (None: gone)
    folder, name = _split(board)
    was = entry_bytes(name, old) if old is not None else 0
    now = entry_bytes(name, new) if new is not None else 0
    blocks = (data_blocks(new) if new is not None else 0) - (data_blocks(old) if old is not None else 0)
    _change(st, folder, now - was, blocks)


def _size(host, host_path):
    try:
        st = host.stat(host_path)
    except OSError:
        return None
    return st[6] if st[0] & _FILE else None


def _count(host, root, st, board):
    host_folder = "/".join([root] + ([board] if board else []))
    meta = st[0]
    meta[board] = _ROOT if not board else 0
    for entry in host.ilistdir(host_folder):
        name = entry[0]
        if entry[1] == _DIR:
            meta[board] += entry_bytes(name)
            _count(host, root, st, board + "/" + name if board else name)
        else:
            size = host.stat(host_folder + "/" + name)[6]
            meta[board] += entry_bytes(name, size)
            st[1] += data_blocks(size)
    st[1] += pair_blocks(meta[board])


def _host_path(root, shim, cwd, path, write=False):
    # (the board path, the host path) of a path the firmware names
    parts = _parts(path, cwd)
    if parts and parts[0] == SHIM:
        if write:
            raise OSError(_EROFS)
        return None, "/".join([shim] + parts[1:])
    if write and not parts:
        raise OSError(_EROFS)  # (/ itself)
    return "/".join(parts), "/".join([root] + parts) or "/"


class _File(_IOBase):
    # a file open for writing: a write that grows it takes the flash's blocks first. It holds
    # its key and the board's op (what the firmware may do anyway), never the host file. An
    # io.IOBase, so print(file=f) and json.dump(x, f) write through it as on a board's file.
    def __init__(self, op, key):
        self._op, self._key = op, key

    def write(self, buf):
        return self._op("write", self._key, buf)

    def _do(self, name, args):  # (the host file's bound method: no __self__ in MicroPython)
        return self._op("attr", self._key, name)(*args)

    def read(self, *args):
        return self._do("read", args)

    def readinto(self, *args):
        return self._do("readinto", args)

    def readline(self, *args):
        return self._do("readline", args)

    def readlines(self, *args):
        return self._do("readlines", args)

    def seek(self, *args):
        return self._do("seek", args)

    def tell(self):
        return self._do("tell", ())

    def flush(self):
        return self._do("flush", ())

    def close(self):
        self._op("close", self._key)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __iter__(self):
        return self

    def __next__(self):
        line = self._do("readline", ())
        if not line:
            raise StopIteration
        return line


class _Board:
    # the board's flash as MicroPython's VFS calls it: each method is one of the op's
    def __init__(self, op):
        self._op = op

    def mount(self, readonly, mkfs):
        pass

    def umount(self):
        pass

    def chdir(self, path):
        self._op("chdir", path)

    def getcwd(self):
        return self._op("getcwd")

    def ilistdir(self, path):
        return self._op("ilistdir", path)

    def stat(self, path):
        return self._op("stat", path)

    def open(self, path, mode):
        return self._op("open", path, mode)

    def remove(self, path):
        self._op("remove", path)

    def rename(self, old, new):
        self._op("rename", old, new)

    def mkdir(self, path):
        self._op("mkdir", path)

    def rmdir(self, path):
        self._op("rmdir", path)

    def statvfs(self, path):
        # (extmod/vfs_lfsx.c statvfs: bsize, frsize, blocks, bfree, bavail, 0, 0, 0, 0, namemax)
        return self._op("statvfs")


def _write(host, st, f, board, append, host_path, buf):
    old = _size(host, host_path) or 0
    end = (old if append else f.tell()) + len(buf)
    if end > old and len(buf):
        _resize(st, board, old, end)  # (ENOSPC here: nothing written)
    else:
        end = old
    try:
        return f.write(buf)
    finally:
        now = _size(host, host_path) or 0
        if now != end:  # (a short or failed write: the count follows the file)
            _resize(st, board, end, now)


def _open(host, st, board, host_path, mode):
    size = _size(host, host_path)
    if size is None:
        _resize(st, board, None, 0)  # (a new entry in its folder's metadata)
        try:
            return host.open(host_path, mode)
        except OSError:
            _resize(st, board, 0, None)
            raise
    f = host.open(host_path, mode)
    if "w" in mode and size:
        _resize(st, board, size, 0)  # truncated
    return f


def _rename(host, st, old_board, old_host, new_board, new_host):
    size = _size(host, old_host)
    target = _size(host, new_host)
    if size is not None and old_board != new_board:
        # the new entry (over the replaced file's) first: ENOSPC leaves all as it was
        _resize(st, new_board, target, size)
        try:
            host.rename(old_host, new_host)
        except OSError:
            _resize(st, new_board, size, target)
            raise
        _resize(st, old_board, size, None)
        return
    if old_board == new_board:
        host.rename(old_host, new_host)  # (onto itself: nothing moves, nothing is freed)
        return
    # a folder: its entry moves to the new parent (first: ENOSPC leaves all as it was)
    old_parent, old_name = _split(old_board)
    new_parent, new_name = _split(new_board)
    try:
        replaced = host.stat(new_host)[0] & _DIR  # (an empty folder there goes)
    except OSError:
        replaced = 0
    if not replaced:
        _change(st, new_parent, entry_bytes(new_name), 0)
    try:
        host.rename(old_host, new_host)
    except OSError:
        if not replaced:
            _change(st, new_parent, -entry_bytes(new_name), 0)
        raise
    _change(st, old_parent, -entry_bytes(old_name), 0)
    meta = st[0]
    if replaced:
        st[1] -= pair_blocks(meta.pop(new_board, 0))
    moved = {}
    for folder in list(meta):
        if folder == old_board or folder.startswith(old_board + "/"):
            moved[new_board + folder[len(old_board) :]] = meta.pop(folder)
    meta.update(moved)


def _mkdir(host, st, board, host_path):
    folder, name = _split(board)
    _change(st, folder, entry_bytes(name), 0, new_folder=board)
    try:
        host.mkdir(host_path)
    except OSError:
        st[0].pop(board, None)
        _change(st, folder, -entry_bytes(name), -pair_blocks(0))
        raise


def _rmdir(host, st, board, host_path):
    host.rmdir(host_path)
    folder, name = _split(board)
    _change(st, folder, -entry_bytes(name), -pair_blocks(st[0].pop(board, 0)))


def _board(host, root, shim, flash_bytes):  # noqa: C901  (one closure: the host in no attribute)
    """The mounted object: the host, the copy's path, the count and the open host files are
    in the closure of its one op, which only does what a board's VFS does."""
    st = [{}, 0, flash_bytes // _BLOCK]  # (the count: see above)
    cwd = ["/"]
    handles = {}  # an open file's key -> [host file, board path, append]
    serial = [0]
    _count(host, root, st, "")

    def op(name, a=None, b=None):  # noqa: C901  (one closure: the host in no attribute)
        if name in ("write", "attr", "close"):
            found = handles.pop(a, None) if name == "close" else handles.get(a)
            if found is None:  # (closed: extmod/vfs_lfsx_file.c check_open, a bare ValueError)
                if name == "close":
                    return None
                raise ValueError()
            if name == "close":
                return found[0].close()
            if name == "attr":
                if b not in _READS:  # (never the host file's own write)
                    raise AttributeError(b)
                return getattr(found[0], b)
            return _write(host, st, found[0], found[1], found[2], _host_path(root, shim, "/", found[1])[1], b)
        if name == "statvfs":
            free = max(0, st[2] - st[1])
            return (_BLOCK, _BLOCK, st[2], free, free, 0, 0, 0, 0, 255)
        if name == "getcwd":
            return cwd[0]
        if name in ("stat", "ilistdir", "chdir") or (name == "open" and not _writes(b)):
            path = _host_path(root, shim, cwd[0], a)[1]
            if name == "open":
                return host.open(path, b)
            if name == "chdir":
                if not host.stat(path)[0] & _DIR:
                    raise OSError(_ENOTDIR)
                cwd[0] = "/" + "/".join(_parts(a, cwd[0]))
                return None
            return host.stat(path) if name == "stat" else host.ilistdir(path)
        board, path = _host_path(root, shim, cwd[0], a, True)
        if name == "open":
            serial[0] += 1  # (a key never reused: a closed file's object stays closed)
            handles[serial[0]] = [_open(host, st, board, path, b), board, "a" in b]
            return _File(op, serial[0])
        if name == "remove":
            size = _size(host, path)
            host.remove(path)
            if size is not None:
                _resize(st, board, size, None)
        elif name == "rename":
            _rename(host, st, board, path, *_host_path(root, shim, cwd[0], b, True))
        elif name == "mkdir":
            _mkdir(host, st, board, path)
        elif name == "rmdir":
            _rmdir(host, st, board, path)
        return None

    return _Board(op)


def _writes(mode):
    return "w" in mode or "a" in mode or "x" in mode or "+" in mode
