# Confine the firmware to its board (docs/shim.md, "Only a board's modules"; docs/security.md).
# Called by _hilboot once the shim has started (it keeps what it took from the host: the
# link's pty, the real select and time) and before boot.py runs:
# - the board's flash at / (_hilfs), the firmware's path as a board's: the shim, /, /lib;
# - the unix port's host reach taken away: os.system, os.getenv/putenv/unsetenv, os.errno,
#   os.VfsPosix and vfs.VfsPosix go; ffi, socket, _thread and termios import as on a port
#   without them (ImportError), unless the rig file allows one by name ([board] allow_modules).
import builtins
import sys

HOST_MODULES = ("ffi", "socket", "usocket", "_thread", "termios")
OS_HOST_NAMES = ("system", "getenv", "putenv", "unsetenv", "errno", "VfsPosix", "unlink")


class _Module:
    pass


def _without(module, names):
    copy = _Module()
    for name in dir(module):
        if not name.startswith("__") and name not in names:
            setattr(copy, name, getattr(module, name))
    return copy


_importing = [None] * 64  # the absolute imports under way, innermost last (no allocation)
_depth = [0]


def _relative(real, name, fromlist, level):
    # A relative import reached here in the shim's globals, not the importing module's
    # (MicroPython passes __import__ no globals): made absolute in the package of the module
    # being imported (the innermost import under way), as MicroPython does with the
    # importer's __name__; at run time (no import under way), in each loaded package in
    # turn, the firmware's before the frozen ones (asyncio), the first that has what it
    # names wins. A relative import never reaches a host module.
    depth = _depth[0]
    if 0 < depth <= len(_importing):
        importer = _importing[depth - 1]
        module = sys.modules.get(importer)
        package = importer if getattr(module, "__path__", None) is not None else importer.rpartition(".")[0]
        if level > 1:
            package = package.rsplit(".", level - 1)[0]
        if package:
            return real(package + "." + name if name else package, None, None, fromlist, 0)
    error = ImportError("can't perform relative import")
    packages = [p for p, m in list(sys.modules.items()) if getattr(m, "__path__", None) is not None]
    packages.sort(key=lambda p: str(getattr(sys.modules[p], "__path__", "")).startswith(".frozen"))
    for package in packages:
        base = package.rsplit(".", level - 1)[0] if level > 1 else package
        target = base + "." + name if name else base
        try:
            module = real(target, None, None, fromlist, 0)
        except ImportError as e:
            error = e
            continue
        names = fromlist if isinstance(fromlist, (tuple, list)) else ()  # (asyncio passes True)
        if all(_has(real, module, target, item) for item in names):
            return module
    raise error


def _has(real, module, target, item):
    if item == "*" or hasattr(module, item):
        return True
    try:
        real(target + "." + item, None, None, None, 0)
    except ImportError:
        return False
    return True


def _board_import(real, blocked):
    dotted = tuple(name + "." for name in blocked)

    def board_import(name, globals=None, locals=None, fromlist=(), level=0):
        # (allocates nothing on the way to an allowed module: imports run under heap_lock too)
        if level:
            return _relative(real, name, fromlist, level)
        if name in blocked:
            raise ImportError("no module named '%s'" % name)
        for prefix in dotted:
            if name.startswith(prefix):
                raise ImportError("no module named '%s'" % name)
        if name in sys.modules:
            return real(name, globals, locals, fromlist, level)
        depth = _depth[0]  # (a first import: its relative imports are made in its package)
        if depth < len(_importing):
            _importing[depth] = name
        _depth[0] = depth + 1
        try:
            return real(name, globals, locals, fromlist, level)
        finally:
            _depth[0] = depth

    return board_import


def confine(env, shim_dir):
    """``env``: the host's settings (read before os.getenv goes): HIL_BOARD_FS (the board's
    folder on the host; none: the firmware's own folders, unconfined), HIL_FLASH_BYTES,
    HIL_ALLOW (names the rig file allows: modules, or os.<name>)."""
    allowed = [n for n in (env.get("HIL_ALLOW") or "").split(",") if n]
    root = env.get("HIL_BOARD_FS")
    if root:
        import _hilfs

        _hilfs.mount(root, int(env.get("HIL_FLASH_BYTES") or 2 * 1024 * 1024), shim_dir)
        sys.path[:] = ["/_hil", "", "/lib", ".frozen"]
    import vfs

    board_os = sys.modules["os"]  # (the shim's board os: _hilsys)
    for name in OS_HOST_NAMES:
        if "os." + name not in allowed and hasattr(board_os, name):
            delattr(board_os, name)
    if "vfs.VfsPosix" not in allowed:
        sys.modules["vfs"] = _without(vfs, ("VfsPosix",))
    blocked = tuple(m for m in HOST_MODULES if m not in allowed)
    board_open = _board_open(builtins.open)
    real_io = _builtin("io")
    board_io = _without(real_io, ("open",))
    board_io.open = board_open
    sys.modules["io"] = board_io
    builtins.open = board_open
    _scrub(allowed, blocked, shim_dir, sys.modules["vfs"], real_io, board_io)
    builtins.__import__ = _board_import(builtins.__import__, blocked)


def _board_open(real):
    # open() as a board's VFS has it: a path, never a number. (The unix port's
    # extmod/vfs.c mp_vfs_open hands a small int straight to VfsPosix, a host file
    # descriptor: the link's pty, stdin; a board's lookup_path takes the path as a str:
    # TypeError.)
    def open(file, *args, **kwargs):
        if not isinstance(file, (str, bytes)):
            raise TypeError("can't convert '%s' object to str implicitly" % type(file).__name__)
        return real(file, *args, **kwargs)

    return open


def _builtin(name):
    # the built-in module itself, under the shim's entry in sys.modules
    mine = sys.modules.pop(name, None)
    try:
        return __import__(name)
    finally:
        if mine is not None:
            sys.modules[name] = mine


def _scrub(allowed, blocked, shim_dir, board_vfs, real_io, board_io):
    """No host handle stays on the shim's own modules (docs/security.md, "The shim's objects
    hold no host handle"): a module global that is the unix port's os, vfs or io becomes a
    copy without the host's names (io's open takes no file descriptor), a host module (ffi,
    socket, ...) goes, and a module's __file__ names its board path (/_hil/...), not the
    host's."""
    real_os, real_vfs = _builtin("os"), _builtin("vfs")
    safe_os = _without(real_os, tuple(n for n in OS_HOST_NAMES if "os." + n not in allowed))
    host = [sys.modules[m] for m in blocked if m in sys.modules]
    prefix = shim_dir.rstrip("/") + "/"
    for module in list(sys.modules.values()):
        names = getattr(module, "__dict__", None)
        if names is None or module is sys or module is builtins:
            continue
        for name in list(names):
            value = names[name]
            try:
                if value is real_os:
                    names[name] = safe_os
                elif value is real_vfs:
                    names[name] = board_vfs
                elif value is real_io:
                    names[name] = board_io
                elif any(value is h for h in host):
                    del names[name]
                elif name == "__file__" and isinstance(value, str) and value.startswith(prefix):
                    names[name] = "/_hil/" + value[len(prefix) :]
            except (TypeError, AttributeError):
                pass  # (a built-in module's names are in ROM, and hold none of these)
    for m in blocked:
        sys.modules.pop(m, None)
