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
    builtins.__import__ = _board_import(builtins.__import__, blocked)
