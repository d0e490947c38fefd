# The board's filesystem, as a MicroPython VFS mounted at / (docs/shim.md, "The board's
# filesystem"): a per-run copy of what `make flash` puts on the board, made by the host
# (host/rig/boardfs.py). Every path the firmware names (open, os.listdir, os.stat,
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
# copy's host path and the open host files live in the closures of `mount` (MicroPython
# has no __closure__), never in an attribute, a global or a mounted object's field.
_ENOSPC, _EROFS, _ENOTDIR, _EBADF = 28, 30, 20, 9  # (MicroPython's errno names few of them)

_BLOCK = 4096  # a board filesystem's block (littlefs on 4 KiB flash sectors)
_INLINE = 128  # littlefs's inline_max under MicroPython's VfsLfs2 (see above)
_HALF = _BLOCK // 2  # a metadata pair's entries before littlefs splits it
_TAG = 12  # create + name + struct tags of an entry
_ROOT = _TAG + 8 + 24  # the superblock's entry in the root pair ("littlefs", its 24 bytes)
_DIR = 0x4000
_FILE = 0x8000
SHIM = "_hil"  # where the shim's folder is seen


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


def _board(host, root, shim, flash_bytes):  # noqa: C901  (its closures hold the host: one scope by design)
    total = flash_bytes // _BLOCK
    cwd = ["/"]
    meta = {}  # board folder ("" is /) -> bytes of its entries
    used = [0]  # blocks in use
    handles = {}  # an open file's key -> [host file, board path, append]
    serial = [0]

    def path_of(path):
        parts = _parts(path, cwd[0])
        if parts and parts[0] == SHIM:
            return "/".join([shim] + parts[1:])
        return "/".join([root] + parts) or "/"

    def writable(path):
        # (the board path and the host path) of a path the firmware may write
        parts = _parts(path, cwd[0])
        if parts and parts[0] == SHIM:
            raise OSError(_EROFS)
        if not parts:
            raise OSError(_EROFS)  # (/ itself)
        return "/".join(parts), "/".join([root] + parts)

    def split(board):
        folder, _, name = board.rpartition("/")
        return folder, name

    def size_of(host_path):
        try:
            st = host.stat(host_path)
        except OSError:
            return None
        return st[6] if st[0] & _FILE else None

    def change(folder, dmeta, ddata, new_folder=None):
        """Take (or give back) ``dmeta`` bytes of ``folder``'s metadata and ``ddata`` blocks;
        ENOSPC, nothing changed, when the flash has not the blocks."""
        before = meta.get(folder, 0)
        after = before + dmeta
        grow = pair_blocks(after) - pair_blocks(before) + ddata
        if new_folder is not None:
            grow += pair_blocks(0)
        if grow > 0 and grow > total - used[0]:
            raise OSError(_ENOSPC)
        meta[folder] = after
        if new_folder is not None:
            meta[new_folder] = 0
        used[0] += grow

    def resize(board, old, new):
        """A file's size from ``old`` (None: new) to ``new`` (None: gone)."""
        folder, name = split(board)
        was = entry_bytes(name, old) if old is not None else 0
        now = entry_bytes(name, new) if new is not None else 0
        blocks = (data_blocks(new) if new is not None else 0) - (data_blocks(old) if old is not None else 0)
        change(folder, now - was, blocks)

    def count(board):
        host_folder = "/".join([root] + ([board] if board else []))
        meta[board] = _ROOT if not board else 0
        for entry in host.ilistdir(host_folder):
            name = entry[0]
            inner = board + "/" + name if board else name
            if entry[1] == _DIR:
                meta[board] += entry_bytes(name)
                count(inner)
            else:
                size = host.stat(host_folder + "/" + name)[6]
                meta[board] += entry_bytes(name, size)
                used[0] += data_blocks(size)
        used[0] += pair_blocks(meta[board])

    count("")

    def opened(key):
        found = handles.get(key)
        if found is None:
            raise OSError(_EBADF)
        return found

    class File:
        # a file open for writing: a write that grows it takes the flash's blocks first
        def __init__(self, key):
            self._key = key

        def write(self, buf):
            f, board, append = opened(self._key)
            host_path = path_of("/" + board)
            old = size_of(host_path) or 0
            end = (old if append else f.tell()) + len(buf)
            if end > old and len(buf):
                resize(board, old, end)  # (ENOSPC here: nothing written)
            else:
                end = old
            try:
                return f.write(buf)
            finally:
                now = size_of(host_path) or 0
                if now != end:  # (a short or failed write: the count follows the file)
                    resize(board, end, now)

        def read(self, *n):
            return opened(self._key)[0].read(*n)

        def readinto(self, *buf):
            return opened(self._key)[0].readinto(*buf)

        def readline(self, *n):
            return opened(self._key)[0].readline(*n)

        def readlines(self):
            return opened(self._key)[0].readlines()

        def seek(self, *where):
            return opened(self._key)[0].seek(*where)

        def tell(self):
            return opened(self._key)[0].tell()

        def flush(self):
            return opened(self._key)[0].flush()

        def close(self):
            found = handles.pop(self._key, None)
            if found is not None:
                found[0].close()

        def __enter__(self):
            return self

        def __exit__(self, *exc):
            self.close()

        def __iter__(self):
            return self

        def __next__(self):
            line = opened(self._key)[0].readline()
            if not line:
                raise StopIteration
            return line

    class Board:
        """The board's flash: a folder of the host counted as a littlefs of its size."""

        def mount(self, readonly, mkfs):
            pass

        def umount(self):
            pass

        def chdir(self, path):
            parts = _parts(path, cwd[0])
            if not host.stat(path_of("/" + "/".join(parts)))[0] & _DIR:
                raise OSError(_ENOTDIR)
            cwd[0] = "/" + "/".join(parts)

        def getcwd(self):
            return cwd[0]

        def ilistdir(self, path):
            return host.ilistdir(path_of(path))

        def stat(self, path):
            return host.stat(path_of(path))

        def open(self, path, mode):
            if not ("w" in mode or "a" in mode or "x" in mode or "+" in mode):
                return host.open(path_of(path), mode)
            board, host_path = writable(path)
            size = size_of(host_path)
            if size is None:
                resize(board, None, 0)  # (a new entry in its folder's metadata)
                try:
                    f = host.open(host_path, mode)
                except OSError:
                    resize(board, 0, None)
                    raise
            else:
                f = host.open(host_path, mode)
                if "w" in mode and size:
                    resize(board, size, 0)  # truncated
            serial[0] += 1
            handles[serial[0]] = [f, board, "a" in mode]
            return File(serial[0])

        def remove(self, path):
            board, host_path = writable(path)
            size = size_of(host_path)
            host.remove(host_path)
            if size is not None:
                resize(board, size, None)

        def rename(self, old, new):
            old_board, old_host = writable(old)
            new_board, new_host = writable(new)
            size = size_of(old_host)
            target = size_of(new_host)
            if size is not None and old_board != new_board:
                # the new entry (over the replaced file's) first: ENOSPC leaves all as it was
                resize(new_board, target, size)
                try:
                    host.rename(old_host, new_host)
                except OSError:
                    resize(new_board, size, target)
                    raise
                resize(old_board, size, None)
                return
            if old_board == new_board:
                host.rename(old_host, new_host)  # (onto itself: nothing moves, nothing is freed)
                return
            # a folder: its entry moves to the new parent (first: ENOSPC leaves all as it was)
            old_parent, old_name = split(old_board)
            new_parent, new_name = split(new_board)
            try:
                replaced = host.stat(new_host)[0] & _DIR  # (an empty folder there goes)
            except OSError:
                replaced = 0
            if not replaced:
                change(new_parent, entry_bytes(new_name), 0)
            try:
                host.rename(old_host, new_host)
            except OSError:
                if not replaced:
                    change(new_parent, -entry_bytes(new_name), 0)
                raise
            change(old_parent, -entry_bytes(old_name), 0)
            if replaced:
                used[0] -= pair_blocks(meta.pop(new_board, 0))
            moved = {}
            for folder in list(meta):
                if folder == old_board or folder.startswith(old_board + "/"):
                    moved[new_board + folder[len(old_board) :]] = meta.pop(folder)
            meta.update(moved)

        def mkdir(self, path):
            board, host_path = writable(path)
            folder, name = split(board)
            change(folder, entry_bytes(name), 0, new_folder=board)
            try:
                host.mkdir(host_path)
            except OSError:
                meta.pop(board, None)
                change(folder, -entry_bytes(name), -pair_blocks(0))
                raise

        def rmdir(self, path):
            board, host_path = writable(path)
            host.rmdir(host_path)
            folder, name = split(board)
            mine = meta.pop(board, 0)
            change(folder, -entry_bytes(name), -pair_blocks(mine))

        def statvfs(self, path):
            # (extmod/vfs_lfsx.c statvfs: bsize, frsize, blocks, bfree, bavail, 0, 0, 0, 0, namemax)
            free = max(0, total - used[0])
            return (_BLOCK, _BLOCK, total, free, free, 0, 0, 0, 0, 255)

    return Board()
