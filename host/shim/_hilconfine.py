# Confine the firmware to its board (docs/shim.md, "Only a board's modules"; docs/security.md).
# Called by _hilboot once the shim has started (it keeps what it took from the host: the
# link's pty, the real select and time) and before boot.py runs:
# - the board's flash at / (_hilfs), the firmware's path as a board's: /, .frozen, /lib, then
#   the shim's folder; a name the loop provides gives its module or the firmware's as the
#   board's sys.path and built-ins give it (BOARD_MODULES); a relative import is made in its
#   importer's package;
# - the unix port's host reach taken away: os.system, os.getenv/putenv/unsetenv, os.errno,
#   os.VfsPosix and vfs.VfsPosix go; ffi, socket, _thread and termios import as on a port
#   without them (ImportError), unless the rig file allows one by name ([board] allow_modules);
#   on a board with a radio, socket and usocket are the board's (_hilsocket: a radio with no
#   network in range), never the host's.
import builtins
import micropython
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


# What each module the loop provides is on a board, as py/builtinimport.c's
# process_import_at_level finds a top-level name: a non-extensible built-in before any
# file; then a file or frozen module along sys.path, which a board starts as
# ['', '.frozen', '/lib'] (py/runtime.c mp_init, ports/rp2/main.c, ports/esp32/main.c);
# an extensible built-in (MP_REGISTER_EXTENSIBLE_MODULE) only when no file has the name.
BUILT_IN = 0  # C (or, rp2, imported by the port's _boot.py before the flash is mounted): never a file's
EXTENSIBLE = 1  # C, registered extensible (extmod/modmachine.c, modtime.c, modselect.c): a file wins
FROZEN = 2  # frozen Python (the ports' manifests require them): a file in / wins, one in /lib does not
BOARD_MODULES = {
    "machine": EXTENSIBLE,
    "time": EXTENSIBLE,
    "select": EXTENSIBLE,
    "neopixel": FROZEN,  # ports/esp32/boards/manifest.py, ports/rp2/boards/manifest.py
    "dht": FROZEN,
    "onewire": FROZEN,
    "ds18x20": FROZEN,
    "_onewire": BUILT_IN,  # extmod/modonewire.c (MICROPY_PY_ONEWIRE on the ESP32 and RP2 ports)
}
# a family's own (ports/rp2/modules/_boot.py imports rp2; ports/esp32/modesp.c registers esp)
FAMILY_MODULES = {"rp2": ("rp2", BUILT_IN), "esp": ("esp", BUILT_IN)}
# a board with a radio's (_hilboards.radio): network is built in (extmod/modnetwork.c,
# MP_REGISTER_MODULE); socket is extensible (extmod/modlwip.c, ports/esp32/modsocket.c:
# MP_REGISTER_EXTENSIBLE_MODULE), the board's _hilsocket put in sys.modules (confine)
RADIO_MODULES = {"network": BUILT_IN}
_U_NAMES = {"machine": "umachine", "time": "utime", "select": "uselect"}  # a board's u-prefix: the built-in itself


def _absolute_name(name, level, importer):
    # py/builtinimport.c evaluate_relative_import: the importer's __name__ less `level`
    # components (one fewer from a package, whose globals have __path__), then the name.
    # (__main__ has no package: on a board, without MICROPY_MODULE_OVERRIDE_MAIN_IMPORT,
    # "can't perform relative import".)
    current = importer.get("__name__") or ""
    if "__path__" in importer:
        level -= 1
    end = len(current)
    while level and end > 0:
        end -= 1
        if current[end] == ".":
            level -= 1
    if end == 0:
        raise ImportError("can't perform relative import")
    return current[:end] + "." + name if name else current[:end]


def _board_import(real, blocked, shim_first, shim_entry, aliases=None):
    dotted = tuple(name + "." for name in blocked)
    aliases = aliases or {}  # a board's module (its name) the shim's module of another name stands in for

    def absolute(name, globals=None, locals=None, fromlist=(), level=0):
        # (allocates nothing on the way to an allowed module: imports run under heap_lock too)
        if name in blocked:
            raise ImportError("no module named '%s'" % name)
        if name in aliases and name not in sys.modules:
            sys.path.insert(0, shim_entry)
            try:
                sys.modules[name] = real(aliases[name], None, None, (), 0)
            finally:
                sys.path.pop(0)
        for prefix in dotted:
            if name.startswith(prefix):
                raise ImportError("no module named '%s'" % name)
        if name in shim_first and name not in sys.modules:
            # the board's module wins over the firmware's file of its name (BOARD_MODULES)
            sys.path.insert(0, shim_entry)
            try:
                return real(name, globals, locals, fromlist, level)
            finally:
                sys.path.pop(0)
        return real(name, globals, locals, fromlist, level)

    def relative(name, fromlist, level, importer):
        return absolute(_absolute_name(name, level, importer), None, None, fromlist, 0)

    @micropython.native
    def board_import(name, globals=None, locals=None, fromlist=(), level=0, _abs=absolute, _rel=relative, _g=globals):
        # A relative import is made in the package of the module that makes it, as on a
        # board: MicroPython passes __import__ no globals (py/runtime.c mp_import_name), and
        # a Python function runs in its own module's; native code that reads no global
        # keeps its caller's (py/emitnative.c swaps globals only for a scope that uses
        # them), so globals() here is the importer's, whether at import or at call time.
        if level:
            return _rel(name, fromlist, level, _g())
        return _abs(name, globals, locals, fromlist, level)

    return board_import


def _module_file(entry, name):
    """A file or package of ``name`` in the path entry ``entry``."""
    import os

    base = entry + "/" + name if entry else name
    for path in (base + ".py", base + ".mpy", base):
        try:
            os.stat(path)
            return path
        except OSError:
            pass
    return None


def _board_path(shim_dir):
    """sys.path as a board's, ['', '.frozen', '/lib'], with the shim's folder last (only its
    own modules are found there: which module a name gives is BOARD_MODULES' choice).
    Returns (the firmware's root entry, its library entries, the shim's entry)."""
    path = list(sys.path)
    shim = [p for p in path if p.rstrip("/") in ("/_hil", shim_dir.rstrip("/"))]
    rest = [p for p in path if p not in shim and p != ".frozen"]
    root, libs = (rest[0], rest[1:]) if rest else ("", [])
    sys.path[:] = [root, ".frozen"] + libs + shim
    return root, libs, (shim[0] if shim else shim_dir)


def _radio():
    """The board's radio (_hilboards.radio), or None."""
    from _hilboards import radio

    board = sys.modules.get("sys", sys)
    machine = getattr(getattr(board, "implementation", None), "_machine", "") or ""
    return radio(getattr(board, "platform", ""), machine)


def _shadowing(root, libs):
    """(the loop's modules the board's own module keeps against a firmware file of their
    name; those a firmware file takes from the loop), per BOARD_MODULES."""
    board = sys.modules.get("sys", sys)
    platform = getattr(board, "platform", "")
    table = dict(BOARD_MODULES)
    for prefix, (name, kind) in FAMILY_MODULES.items():
        if platform.startswith(prefix):
            table[name] = kind  # (elsewhere the board has none: the firmware's file, or ImportError)
    if _radio():
        table.update(RADIO_MODULES)  # (elsewhere: the firmware's network.py, or ImportError)
    shim_first, firmware_first = [], []
    for name, kind in table.items():
        in_root = _module_file(root, name) is not None
        in_lib = any(_module_file(lib, name) is not None for lib in libs)
        if kind == BUILT_IN and (in_root or in_lib) or kind == FROZEN and in_lib and not in_root:
            shim_first.append(name)
        elif kind == EXTENSIBLE and (in_root or in_lib):
            firmware_first.append(name)
    return tuple(shim_first), tuple(firmware_first)


_shim_first = []  # names the shim's folder gives, whatever the firmware's path holds
_firmware_first = []  # names the firmware's file takes from the shim's module (give_way)


def give_way():
    """The firmware's own machine.py, time.py or select.py takes the name from the shim's
    module, as a file takes it from an extensible built-in on a board (called once the
    shim has imported all it keeps, before boot.py). umachine, utime and uselect stay the
    shim's: on a board the u-prefix names the built-in itself (py/objmodule.c
    mp_module_get_builtin)."""
    for name in _firmware_first:
        _shim_first.remove(name)
        mine = sys.modules.pop(name, None)
        if mine is not None:
            sys.modules[_U_NAMES[name]] = mine


def confine(settings, shim_dir):
    """``settings``: the host's, from WELCOME (_hilframe.unpack_welcome): board_fs (the
    board's folder on the host; empty: the firmware's own folders, unconfined),
    flash_bytes, allow (names the rig file allows, comma-separated: modules, or os.<name>)."""
    allowed = [n for n in settings["allow"].decode().split(",") if n]
    root = settings["board_fs"].decode()
    if root:
        import _hilfs

        _hilfs.mount(root, settings["flash_bytes"], shim_dir)
        sys.path[:] = ["/_hil", "", "/lib", ".frozen"]
    fw_root, fw_libs, shim_entry = _board_path(shim_dir)
    shim_first, _firmware_first[:] = _shadowing(fw_root, fw_libs)
    _shim_first[:] = shim_first + tuple(_firmware_first)  # (the shim's own until give_way)
    import vfs

    board_os = sys.modules["os"]  # (the shim's board os: _hilsys)
    for name in OS_HOST_NAMES:
        if "os." + name not in allowed and hasattr(board_os, name):
            delattr(board_os, name)
    if "vfs.VfsPosix" not in allowed:
        sys.modules["vfs"] = _without(vfs, ("VfsPosix",))
    blocked = tuple(m for m in HOST_MODULES if m not in allowed)
    # A board with a radio has its own socket (the board's, _hilsocket: no host network);
    # the host's goes as on every board, unless the rig file allows it by name.
    board_socket = None
    if _radio() is not None and "socket" not in allowed and "usocket" not in allowed:
        import _hilsocket as board_socket
    # An rp2 or ESP32 board has _thread (its second core, FreeRTOS tasks): the board's,
    # on the one virtual clock (_hilthread), unless the rig file allows the host's by name.
    # (imported only when the firmware imports _thread: until then it takes none of the heap;
    # the unix port's functions it needs are kept now, before the host's module goes)
    aliases = {}
    if _threads_port() and "_thread" not in allowed:
        import _thread

        import _hil

        _hil._Link.thread_api = (_thread.allocate_lock, _thread.start_new_thread)
        aliases["_thread"] = "_hilthread"
    board_open = _board_open(builtins.open)
    real_io = _builtin("io")
    board_io = _without(real_io, ("open",))
    board_io.open = board_open
    sys.modules["io"] = board_io
    builtins.open = board_open
    _scrub(allowed, blocked, shim_dir, sys.modules["vfs"], real_io, board_io)
    if board_socket is not None:
        # usocket is the built-in itself (py/objmodule.c mp_module_get_builtin); socket too,
        # unless the firmware brings a socket.py (an extensible built-in: its file wins)
        sys.modules["usocket"] = board_socket
        if not any(_module_file(p, "socket") for p in [fw_root] + fw_libs):
            sys.modules["socket"] = board_socket
        blocked = tuple(m for m in blocked if m not in ("socket", "usocket"))
    if aliases:
        sys.modules.pop("_thread", None)
        blocked = tuple(m for m in blocked if m not in aliases)
    builtins.__import__ = _board_import(builtins.__import__, blocked, _shim_first, shim_entry, aliases)


def _threads_port():
    """The board's port has _thread (MICROPY_PY_THREAD: ports/rp2/mpconfigport.h,
    ports/esp32/mpconfigport.h)."""
    platform = getattr(sys.modules.get("sys", sys), "platform", "")
    return platform.startswith("rp2") or platform.startswith("esp32")


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
