"""What pins a firmware's code uses, and under which names, as data: read without running it.

``mpy-fil init`` writes a starting rig file from a scan and ``mpy-fil check`` compares one
with the rig's wiring (:mod:`host.rig.scan.pincheck`). The scanner parses the firmware's ``.py``
files (its folder, its library folders, the board file as the module ``board``) and finds
every pin the code makes, as public MicroPython robot code writes them: ``Pin(18, Pin.IN)``,
``machine.Pin(id=18)``, ``Pin(ECHO)`` with ``ECHO = const(18)`` or ``ECHO = 18`` in the same
file or in a module it imports (``import config``, ``from board import *``), ``PWM(Pin(15),
freq=1000)``, ``ADC(Pin(26))`` and ``ADC(0)`` (on an RP2040, ADC channel 0 is GP26: board
files name the GPIO), ``UART(1, tx=4, rx=5)``, tuples and lists of pins walked in a loop or a
comprehension (``ENC_PINS = (2, 3)``), and classes or functions that make a pin of what they
are given (``Motor(16, 17, 18)``, ``HCSR04(trigger_pin=5, echo_pin=18)``). A pin computed at
run time cannot be known here: it is listed as not checked.
"""

import ast
import os
from dataclasses import dataclass, field
from pathlib import Path

from host.core import safefs

SCAN_MAX_FILES = 1000  # .py files a scan reads at most (a board's flash holds far fewer)
SCAN_MAX_BYTES = 8 << 20  # and bytes
NOT_FIRMWARE = {"__pycache__", "node_modules", "site-packages", "build", "dist"}  # and hidden folders, venvs
RP2_ADC_GPIO = {0: 26, 1: 27, 2: 28, 3: 29}  # an RP2040's ADC channels (4: the temperature sensor)
MAKERS = {"Pin": "pin", "Signal": "pin", "PWM": "pwm", "ADC": "adc_id", "UART": "uart"}  # machine's pin makers
BUSES = {"UART", "I2C", "SoftI2C", "SPI", "SoftSPI"}  # their pins are keywords: UART(1, tx=4, rx=5)
BUS_PINS = {"tx", "rx", "scl", "sda", "sck", "mosi", "miso", "cs"}
BUS_NAMES = {"I2C": ("id",), "SPI": ("id",), "SoftI2C": ("scl", "sda"), "SoftSPI": ("sck", "mosi", "miso")}
# (their arguments that name the bus, as the shim names it: i2c0, spi1, i2c:<scl>,<sda>)
DHT_MAKERS = ("DHT11", "DHT22")  # dht.DHT22(Pin(4)): its pin is the sensor's line, dht:4 (host/shim/_hildht.py)
# a maker whose first argument is a line the shim reads a slot or frame at a time -> the line's prefix
LINE_MAKERS = {**dict.fromkeys(DHT_MAKERS, "dht"), "OneWire": "onewire"}  # (OneWire(Pin(4)): onewire:4, _onewire.py)
PIO_MAKERS = {"StateMachine", "init", "state_machine"}  # rp2's: a state machine and its pin groups
PIO_BASES = {"in_base", "out_base", "set_base", "sideset_base"}  # the first pin of a group (its size: the program's)
NOTES_MAX = 5  # files that could not be read, named one by one
LOOP_MAX_PINS = 64  # a longer tuple is not a list of pins (a loop over it is not walked item by item)
FACTORY_PASSES = 6  # a driver made by a driver made by a driver...


@dataclass(frozen=True)
class PinUse:
    """One pin the code makes: ``key`` as the shim names it (``"18"``, ``"GP14"``, ``"uart1"``)."""

    key: str
    call: str  # what the code makes: "Pin(18)", "PWM(Pin(15))", "ADC(0) (GP26)", "UART(1)"
    where: str  # "main.py:12"
    name: str | None  # the code's own name for it: "ECHO", "ENC_PINS[1]", "left.in1"
    kind: str  # pin, pwm, adc, uart, bus (a line of an I2C or SPI bus), pio (a PIO pin group's first pin)


@dataclass
class Scan:
    """A firmware's pins: what it uses, and the pin expressions only a run can tell."""

    uses: list[PinUse] = field(default_factory=list)
    unchecked: list[str] = field(default_factory=list)  # "main.py:30: Pin(cfg['echo'])"
    notes: list[str] = field(default_factory=list)
    buses: dict[str, str] = field(default_factory=dict)  # bus as the shim names it -> where it is made
    buses_unknown: list[str] = field(default_factory=list)  # buses made with arguments only a run can tell

    def by_key(self) -> dict[str, list[PinUse]]:
        keys: dict[str, list[PinUse]] = {}
        for use in self.uses:
            keys.setdefault(use.key, []).append(use)
        return keys


@dataclass(frozen=True)
class _Module:
    ref: str


@dataclass(frozen=True)
class _Param:
    name: str
    many: bool = False  # a list of pins (walked in a loop, indexed)


@dataclass
class _Factory:
    params: list[str]
    pins: dict = field(default_factory=dict)  # param -> (kind, many)


# -- files ---------------------------------------------------------------------------------


def firmware_sources(folder: Path, notes: list | None = None) -> list[Path]:
    """The ``.py`` files of a firmware folder, in order, skipping hidden folders, virtual
    environments (a ``pyvenv.cfg``) and tool folders (``NOT_FIRMWARE``), and stopping at
    ``SCAN_MAX_FILES`` files or ``SCAN_MAX_BYTES`` bytes (said in ``notes``)."""
    found, total = [], 0
    for top, dirs, files in os.walk(folder):
        dirs[:] = sorted(d for d in dirs if not _skipped(Path(top, d)))
        for name in sorted(f for f in files if f.endswith(".py")):
            path = Path(top, name)
            try:
                info = path.stat()
            except OSError:
                continue
            if not safefs.regular_file(path):  # (a FIFO's read waits for ever; a device's never ends)
                if notes is not None:
                    what = safefs.kind(path, follow=True) or "not a regular file"
                    notes.append(f"skipped {path}: {what}, not a file to read")
                continue
            size = info.st_size
            if len(found) >= SCAN_MAX_FILES or total + size > SCAN_MAX_BYTES:
                if notes is not None:
                    notes.append(
                        f"stopped reading at {path} after {len(found)} files, {total} bytes "
                        f"(at most {SCAN_MAX_FILES} files, {SCAN_MAX_BYTES} bytes): some pins may be missing"
                    )
                return found
            found.append(path)
            total += size
    return found


def _skipped(folder: Path) -> bool:
    name = folder.name
    return name.startswith(".") or name in NOT_FIRMWARE or (folder / "pyvenv.cfg").exists() or folder.is_symlink()


def _parse(source: Path, notes: list | None = None):
    try:
        return ast.parse(source.read_text(errors="replace"))
    except (SyntaxError, ValueError, RecursionError, MemoryError, OSError) as e:  # (a NUL, nesting: not firmware)
        if notes is not None:
            why = f"line {e.lineno}: {e.msg}" if isinstance(e, SyntaxError) else type(e).__name__
            notes.append(f"could not read {source} ({why}): its pins are not checked")
        return None


def scan_folder(folder: Path, libs=(), board_file: Path | None = None, entry: str | None = None, family=None) -> Scan:
    """The pins of the firmware in ``folder`` (and ``libs``, searched as a board's path, and
    ``board_file`` as the module ``board``). With ``entry``, only the modules the entry file
    (and ``boot.py``) import, as the board runs them; without, every file. ``family``:
    ``"rp2"`` reads ``ADC(0)`` as GP26."""
    scan = Scan()
    modules: dict[str, tuple[str, ast.Module]] = {}  # module name -> (shown path, tree)
    inside = [Path(lib).resolve() for lib in libs if Path(lib).resolve() != Path(folder).resolve()]
    for root in (folder, *libs):
        for path in firmware_sources(root, scan.notes):
            if root == folder and any(path.resolve().is_relative_to(lib) for lib in inside):
                continue  # (read from its library folder, under the name a board imports it by)
            tree = _parse(path, scan.notes)
            rel = path.relative_to(root)
            name = ".".join(rel.with_suffix("").parts).removesuffix(".__init__")
            if tree is not None and name not in modules:
                shown = path.relative_to(folder if path.is_relative_to(folder) else root.parent)
                modules[name] = (str(shown), tree)
    unread = [n for n in scan.notes if n.startswith("could not read")]
    if len(unread) > NOTES_MAX:  # (a folder of Python 2 files: the first few say it)
        scan.notes = [n for n in scan.notes if n not in unread[NOTES_MAX:]]
        scan.notes.append(f"and {len(unread) - NOTES_MAX} more files could not be read")
    if board_file is not None and board_file.is_file() and (tree := _parse(board_file)) is not None:
        modules.setdefault("board", (board_file.name, tree))
    return scan_modules(modules, _reachable(modules, entry) if entry else list(modules), family, scan)


def scan_modules(modules: dict, run: list[str], family=None, scan: Scan | None = None) -> Scan:
    """The pins the modules named in ``run`` make (``modules``: name -> (shown path, tree))."""
    scan = scan or Scan()
    envs = _Envs(modules)
    factories = _factories(modules, envs)
    makers = MAKERS.keys() | BUSES | PIO_MAKERS | factories.keys()
    for name in run:
        shown, tree = modules[name]
        aliases = _aliases(tree)
        if not _called(tree) & (makers | aliases.keys()):
            continue
        try:
            _Visitor(shown, envs, envs.of(name), factories, family, scan, aliases).visit_body(tree.body)
        except RecursionError:
            scan.notes.append(f"could not read {shown}: nested too deeply; its pins are not checked")
    return scan


def _aliases(tree) -> dict[str, str]:
    """``from machine import Pin as GPIO``: GPIO -> Pin."""
    return {
        alias.asname: alias.name
        for node in ast.walk(tree)
        if isinstance(node, ast.ImportFrom) and node.module in ("machine", "umachine")
        for alias in node.names
        if alias.asname and alias.name in MAKERS.keys() | BUSES
    }


def _called(node) -> set[str]:
    """The names of the functions called under a node (``Pin``, ``machine.Pin``: Pin)."""
    return {_func_name(n) for n in ast.walk(node) if isinstance(n, ast.Call)}


def _reachable(modules: dict, entry: str) -> list[str]:
    start = [m for m in ("boot", entry.removesuffix(".py").replace("/", ".")) if m in modules]
    seen: list[str] = []
    while start:
        name = start.pop()
        if name in seen:
            continue
        seen.append(name)
        for node in ast.walk(modules[name][1]):
            for ref in _imported(node, name, modules):
                parts = ref.split(".")
                start += [".".join(parts[:i]) for i in range(1, len(parts) + 1) if ".".join(parts[:i]) in modules]
    return seen


def _imported(node, importer: str, modules: dict) -> list[str]:
    if isinstance(node, ast.Import):
        return [a.name for a in node.names]
    if isinstance(node, ast.ImportFrom):
        base = _from_base(node, importer, modules)
        if base is None:
            return []
        return [base, *(f"{base}.{a.name}".strip(".") for a in node.names)]
    return []


def _from_base(node: ast.ImportFrom, importer: str, modules: dict) -> str | None:
    """The module a ``from ... import`` reads, by its absolute name: a relative one
    (``from . import sh1106``, ``from ..util import x``) in its importer's package, as
    MicroPython makes it (py/builtinimport.c evaluate_relative_import: the importer's name
    less ``level`` parts, one fewer from a package's ``__init__``); None past the top."""
    if not node.level:
        return node.module or ""
    parts = importer.split(".")
    shown = modules.get(importer, ("",))[0]
    drop = node.level - (1 if shown.endswith("__init__.py") else 0)
    if drop >= len(parts):
        return None
    base = ".".join(parts[: len(parts) - drop])
    return f"{base}.{node.module}" if node.module else base


# -- constants -------------------------------------------------------------------------------


class _Envs:
    """Each module's module-level names: ints, texts, tuples of them, imported modules."""

    def __init__(self, modules: dict):
        self.modules = modules
        self.done: dict[str, dict] = {}

    def of(self, name: str) -> dict:
        if name not in self.done:
            self.done[name] = {}  # (an import cycle sees what is known so far)
            if name in self.modules:
                self.done[name] = self._build(self.modules[name][1].body, {}, name)
        return self.done[name]

    def _build(self, body: list, env: dict, name: str) -> dict:
        for node in body:
            if isinstance(node, ast.Import):
                for alias in node.names:  # import a.b binds a; import a.b as c binds c to a.b
                    ref = alias.name if alias.asname else alias.name.split(".")[0]
                    env[alias.asname or ref] = _Module(ref)
            elif isinstance(node, ast.ImportFrom):
                self._import_from(node, env, name)
            elif isinstance(node, ast.Assign | ast.AnnAssign) and node.value is not None:
                for target in node.targets if isinstance(node, ast.Assign) else [node.target]:
                    self.bind(target, node.value, env)
            elif isinstance(node, ast.Try):
                self._build(node.body, env, name)
        return env

    def _import_from(self, node: ast.ImportFrom, env: dict, importer: str) -> None:
        base = _from_base(node, importer, self.modules)
        if base is None:
            return
        for alias in node.names:
            if alias.name == "*":
                env.update(self.of(base))
            elif f"{base}.{alias.name}".strip(".") in self.modules:
                env[alias.asname or alias.name] = _Module(f"{base}.{alias.name}".strip("."))
            elif alias.name in self.of(base):
                env[alias.asname or alias.name] = self.of(base)[alias.name]

    def bind(self, target, value, env: dict) -> None:
        """``NAME = 18``, ``A, B = 16, 17``: the names bound to what is known of the value."""
        if isinstance(target, ast.Name):
            known = self.value(value, env)
            if known is None:
                env.pop(target.id, None)
            else:
                env[target.id] = known
        elif isinstance(target, ast.Tuple | ast.List) and isinstance(value, ast.Tuple | ast.List):
            for t, v in zip(target.elts, value.elts):
                self.bind(t, v, env)

    def value(self, node, env: dict):  # noqa: C901 (one case a node type)
        """What an expression is known to be: an int, a text, a tuple of them, a module; or None."""
        if isinstance(node, ast.Constant) and type(node.value) in (int, str):
            return node.value
        if isinstance(node, ast.Name):
            return env.get(node.id)
        if isinstance(node, ast.Attribute):
            base = self.value(node.value, env)
            if isinstance(base, _Module):
                sub = f"{base.ref}.{node.attr}"
                return _Module(sub) if sub in self.modules else self.of(base.ref).get(node.attr)
            return None
        if isinstance(node, ast.Call) and _func_name(node) in ("const", "int") and len(node.args) == 1:
            return self.value(node.args[0], env)
        if isinstance(node, ast.Tuple | ast.List):
            items = tuple(self.value(e, env) for e in node.elts)
            return items if all(isinstance(i, int | str) for i in items) else None
        if isinstance(node, ast.Subscript):
            base, index = self.value(node.value, env), self.value(node.slice, env)
            ok = isinstance(base, tuple) and isinstance(index, int) and -len(base) <= index < len(base)
            return base[index] if ok else None
        if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Add | ast.Sub | ast.Mult):
            left, right = self.value(node.left, env), self.value(node.right, env)
            if type(left) is int and type(right) is int:
                return {ast.Add: left + right, ast.Sub: left - right, ast.Mult: left * right}[type(node.op)]
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
            inner = self.value(node.operand, env)
            return -inner if type(inner) is int else None
        return None


def _func_name(call: ast.Call) -> str:
    func = call.func
    return func.id if isinstance(func, ast.Name) else func.attr if isinstance(func, ast.Attribute) else ""


def _code_name(node) -> str | None:
    """The code's own name for an expression: ``ECHO``, ``board.ECHO`` -> ECHO, ``PINS[1]``."""
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        return node.attr
    if isinstance(node, ast.Subscript) and isinstance(node.slice, ast.Constant):
        base = _code_name(node.value)
        return f"{base}[{node.slice.value}]" if base else None
    return None


def _target_name(target) -> str | None:
    """``echo = ...``, ``self.echo = ...``: echo."""
    if isinstance(target, ast.Name):
        return target.id
    if isinstance(target, ast.Attribute):
        return target.attr.lstrip("_") or None
    return None


# -- drivers ---------------------------------------------------------------------------------


def _factories(modules: dict, envs: _Envs) -> dict[str, _Factory]:
    """Classes and functions that make a pin of a parameter: name -> which parameters."""
    found: dict[str, tuple[_Factory, ast.AST, str, set[str], dict]] = {}
    for name in modules:
        aliases = _aliases(modules[name][1])
        for node in modules[name][1].body:
            params = _signature(node)
            if params:
                called = {aliases.get(n, n) for n in _called(node)}
                found[node.name] = (_Factory(params), node, name, called, aliases)
    factories = {n: f for n, (f, *_) in found.items()}
    makers = set(MAKERS) | PIO_MAKERS
    for _ in range(FACTORY_PASSES):
        before = {n: dict(f.pins) for n, f in factories.items()}
        for factory, node, module, called, aliases in found.values():
            if called & makers:
                try:
                    visitor = _Visitor("", envs, envs.of(module), factories, None, Scan(), aliases, learning=factory)
                    visitor.visit_body([node])
                except RecursionError:
                    continue
        makers |= {n for n, f in factories.items() if f.pins}
        if before == {n: dict(f.pins) for n, f in factories.items()}:
            break
    return {n: f for n, f in factories.items() if f.pins}


def _signature(node) -> list[str] | None:
    """A function's parameters, or a class's ``__init__``'s after ``self``."""
    if isinstance(node, ast.ClassDef):
        init = next((n for n in node.body if isinstance(n, ast.FunctionDef) and n.name == "__init__"), None)
        return None if init is None else _signature(init)[1:]
    if isinstance(node, ast.FunctionDef):
        return [a.arg for a in [*node.args.posonlyargs, *node.args.args, *node.args.kwonlyargs]]
    return None


def _self_attrs(node: ast.ClassDef) -> dict:
    """``self.pin = pin`` in a class's methods: attribute -> the parameter it holds."""
    params: set[str] = set()
    held = {}
    for sub in ast.walk(node):
        if isinstance(sub, ast.arguments):
            params |= {a.arg for a in [*sub.args, *sub.kwonlyargs]}
        elif isinstance(sub, ast.Assign) and isinstance(sub.value, ast.Name):
            for target in sub.targets:
                if isinstance(target, ast.Attribute) and getattr(target.value, "id", "") == "self":
                    held[target.attr] = _Param(sub.value.id)
    return {attr: param for attr, param in held.items() if param.name in params}


# -- the walk --------------------------------------------------------------------------------


class _Visitor:
    """Walks one module (or one driver, to learn its parameters), scope by scope."""

    def __init__(self, shown: str, envs: _Envs, env: dict, factories: dict, family, scan: Scan, aliases, learning=None):
        self.shown, self.envs, self.env, self.factories, self.family = shown, envs, dict(env), factories, family
        self.scan, self.learning = scan, learning  # learning: the driver whose pin parameters are sought
        self.aliases = aliases  # from machine import Pin as GPIO: GPIO -> Pin
        self.params: dict[str, _Param] = {}  # the parameters of the functions around
        self.self_attrs: dict = {}  # self.pin = pin in the class around
        self.loop_names: dict[str, str | None] = {}  # a loop's variable -> the name of the pin it is now
        self.done: set[int] = set()  # calls already read as the argument of another

    def visit_body(self, body: list) -> None:
        for node in body:
            self.visit(node)

    def visit(self, node) -> None:
        if isinstance(node, ast.ClassDef):
            saved_attrs, self.self_attrs = self.self_attrs, _self_attrs(node)
            self.visit_body(node.body)
            self.self_attrs = saved_attrs
            return
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            saved = dict(self.env), dict(self.params)
            args = node.args
            for a in [*args.posonlyargs, *args.args, *args.kwonlyargs, args.vararg, args.kwarg]:
                if a is not None:
                    self.env.pop(a.arg, None)
                    self.params[a.arg] = _Param(a.arg)
            self.visit_body(node.body)
            self.env, self.params = saved
            return
        if isinstance(node, ast.Assign | ast.AnnAssign) and node.value is not None:
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            self._expr(node.value, _target_name(targets[0]) if len(targets) == 1 else None)
            for target in targets:
                self._bind(target, node.value)
            return
        if isinstance(node, ast.For | ast.AsyncFor):
            self._expr(node.iter, None)
            self._loop(node.target, node.iter, lambda: self.visit_body(node.body + node.orelse))
            return
        if isinstance(node, ast.expr):
            self._expr(node, None)
            return
        for child in ast.iter_child_nodes(node):
            self.visit(child)

    def _bind(self, target, value) -> None:
        self.envs.bind(target, value, self.env)
        if isinstance(target, ast.Name):
            self.params.pop(target.id, None)

    def _loop(self, target, iterable, then) -> None:
        """A loop over pins: its variable is each of them in turn (or a driver's list parameter)."""
        if not isinstance(target, ast.Name):
            then()
            return
        known = self.envs.value(iterable, self.env)
        param = self._param(iterable)
        saved_env, saved_param = self.env.get(target.id), self.params.get(target.id)
        if param is not None:
            self.params[target.id] = _Param(param.name, many=True)
            self.env.pop(target.id, None)
            then()
        elif isinstance(known, tuple) and len(known) <= LOOP_MAX_PINS and not self.loop_names:
            base = _code_name(iterable)
            for i, item in enumerate(known):
                self.env[target.id] = item
                self.loop_names[target.id] = f"{base}[{i}]" if base else None
                then()
            self.loop_names.pop(target.id, None)
        else:
            self.env.pop(target.id, None)
            then()
        self.params.pop(target.id, None)
        for store, saved in ((self.env, saved_env), (self.params, saved_param)):
            if saved is not None:
                store[target.id] = saved

    def _param(self, node) -> _Param | None:
        """The driver parameter an expression is, if it is one (``pin``, ``pins[0]``, ``self.pin``)."""
        if isinstance(node, ast.Name):
            return self.params.get(node.id)
        if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id == "self":
            return self.self_attrs.get(node.attr)
        if isinstance(node, ast.Subscript):
            inner = self._param(node.value)
            return _Param(inner.name, many=True) if inner else None
        return None

    def _expr(self, node, target: str | None) -> None:
        """Every pin-making call in an expression; ``target``: the name it is assigned to."""
        if isinstance(node, ast.ListComp | ast.GeneratorExp | ast.SetComp) and len(node.generators) == 1:
            gen = node.generators[0]
            self._expr(gen.iter, None)
            self._loop(gen.target, gen.iter, lambda: self._expr(node.elt, target))
            return
        if isinstance(node, ast.Lambda):
            return
        if isinstance(node, ast.Call) and id(node) not in self.done:
            self._call(node, target)
        for child in ast.iter_child_nodes(node):
            child = child.value if isinstance(child, ast.keyword) else child  # Pin(...) given as tx=Pin(4)
            if isinstance(child, ast.expr):
                self._expr(child, None)

    def _call(self, call: ast.Call, target: str | None) -> None:
        name = self._maker_name(call)
        if name in MAKERS:
            self._maker(call, name, target)
        elif name in self.factories:
            self._driver(call, name, target)
        for kw in call.keywords if name in BUSES else ():
            if kw.arg in BUS_PINS:
                self._bus_pin(kw.value, name, kw.arg, call)
        for param, arg in zip(BUS_NAMES.get(name, ()), call.args) if name.startswith("Soft") else ():
            self._bus_pin(arg, name, param, call)
        if name in BUS_NAMES and self.learning is None:
            self._bus(call, name)
        for kw in call.keywords if name in PIO_MAKERS else ():
            if kw.arg in PIO_BASES:
                self._pio_base(kw.value, name, kw.arg, call)
        if name in LINE_MAKERS and call.args and self.learning is None:
            self._dht(call, name)

    def _pio_base(self, arg, name: str, param: str, call: ast.Call) -> None:
        """A PIO pin group's first pin (``in_base=Pin(2)`` or ``in_base=2``): the pins after
        it may be the group's too, as many as the program reads or drives."""
        if isinstance(arg, ast.Call) and self._maker_name(arg) in ("Pin", "Signal") and arg.args:
            arg = arg.args[0]  # (its Pin(2) is a pin use of its own as well)
        self._pin(arg, "pio", f"{name}({param}={{}})", call, param)

    def _dht(self, call: ast.Call, name: str) -> None:
        """A DHT sensor's or a 1-Wire bus's pin: a line (dht:<pin>, onewire:<pin>) the shim
        reads a frame or a slot at a time."""
        arg = call.args[0]
        self._bus_pin(arg, name, "pin", call)
        if isinstance(arg, ast.Call) and self._maker_name(arg) in ("Pin", "Signal") and arg.args:
            arg = arg.args[0]
        value = self.envs.value(arg, self.env)
        where = f"{self.shown}:{call.lineno}"
        if isinstance(value, int | str) and type(value) is not bool:
            self.scan.buses.setdefault(f"{LINE_MAKERS[name]}:{value}", f"{where}: {name}(...)")
        else:
            self.scan.buses_unknown.append(f"{where}: {ast.unparse(call)[:80]}")

    def _bus_pin(self, arg, name: str, param: str, call: ast.Call) -> None:
        """A pin a bus is made on (``I2C(0, scl=Pin(5), sda=4)``): a bus line, not a plant
        signal; ``kind`` ``bus`` (a UART's stay pins: the shim names the UART, not them)."""
        if name == "UART":
            self._pin(arg, "pin", f"{name}({param}={{}})", call, param)
            return
        if isinstance(arg, ast.Call) and self._maker_name(arg) in ("Pin", "Signal") and arg.args:
            self.done.add(id(arg))  # (its Pin(5) is this bus's line, not a pin of its own)
            arg = arg.args[0]
        self._pin(arg, "bus", f"{name}({param}={{}})", call, param)

    def _bus(self, call: ast.Call, name: str) -> None:
        """The bus an I2C/SoftI2C/SPI/SoftSPI call makes, named as the shim names it."""
        where = f"{self.shown}:{call.lineno}"
        args = {k.arg: k.value for k in call.keywords if k.arg}
        order = BUS_NAMES[name]
        for param, arg in zip(order, call.args):
            args.setdefault(param, arg)
        values = []
        for param in order[:1] if name in ("I2C", "SPI") else order:
            arg = args.get(param)
            if isinstance(arg, ast.Call) and self._maker_name(arg) in ("Pin", "Signal") and arg.args:
                arg = arg.args[0]
            value = 0 if arg is None and name == "I2C" else self.envs.value(arg, self.env) if arg is not None else None
            if not isinstance(value, int | str) or type(value) is bool:
                self.scan.buses_unknown.append(f"{where}: {ast.unparse(call)[:80]}")
                return
            values.append(str(value))
        kind = "i2c" if "I2C" in name else "spi"
        key = f"{kind}{values[0]}" if name in ("I2C", "SPI") else f"{kind}:{','.join(values)}"
        self.scan.buses.setdefault(key, f"{where}: {name}(...)")

    def _maker_name(self, call: ast.Call) -> str:
        name = _func_name(call)
        return self.aliases.get(name, name) if isinstance(call.func, ast.Name) else name

    def _maker(self, call: ast.Call, name: str, target: str | None) -> None:
        kind = MAKERS[name]
        arg = (
            call.args[0]
            if call.args
            else next((k.value for k in call.keywords if k.arg in ("id", "dest", "pin")), None)
        )
        if arg is None:
            return
        if isinstance(arg, ast.Call) and self._maker_name(arg) in ("Pin", "Signal"):  # PWM(Pin(15)), ADC(Pin(26))
            self.done.add(id(arg))
            inner = arg.args[0] if arg.args else next((k.value for k in arg.keywords if k.arg == "id"), None)
            if inner is not None:
                outer = {"pwm": "pwm", "adc_id": "adc"}.get(kind, "pin")
                self._pin(inner, outer, f"{name}(Pin({{}}))" if name != "Signal" else "Pin({})", arg, target)
            return
        self._pin(arg, kind, f"{name}({{}})", call, target)

    def _driver(self, call: ast.Call, name: str, target: str | None) -> None:
        factory = self.factories[name]
        given = list(zip(factory.params, call.args)) + [(k.arg, k.value) for k in call.keywords if k.arg]
        for param, arg in given:
            if param not in factory.pins or isinstance(arg, ast.Starred):
                continue
            kind, many, inner = factory.pins[param]
            shape = f"{inner} through {name}" if " through " not in inner else inner
            label = f"{target}.{param}" if target else param
            if many and isinstance(arg, ast.Tuple | ast.List):
                for i, item in enumerate(arg.elts):
                    self._pin(item, kind, shape, call, f"{label}[{i}]")
            elif many and isinstance(self.envs.value(arg, self.env), tuple):
                base = _code_name(arg) or label
                for i, item in enumerate(self.envs.value(arg, self.env)):
                    self._use(item, kind, shape, call, f"{base}[{i}]")
            else:
                self._pin(arg, kind, shape, call, label)

    def _pin(self, arg, kind: str, shape: str, call: ast.Call, fallback: str | None) -> None:
        """One pin argument: a use, a driver's parameter learnt, or a pin only a run can tell."""
        param = self._param(arg)
        if param is not None:
            if self.learning is not None:
                self.learning.pins.setdefault(param.name, (kind, param.many, shape))
            return
        if isinstance(arg, ast.Call) and self._maker_name(arg) in MAKERS:  # I2C(scl=Pin(5)): read as itself
            return
        value = self.envs.value(arg, self.env)
        if isinstance(arg, ast.Name) and arg.id in self.loop_names:
            name = self.loop_names[arg.id]
        else:
            name = _code_name(arg) if not isinstance(arg, ast.Constant) else None
        if isinstance(value, int | str) and type(value) is not bool:
            self._use(value, kind, shape, call, name or fallback)
        elif self.learning is None:
            line = f"{self.shown}:{call.lineno}: {ast.unparse(call)[:80]}"
            if line not in self.scan.unchecked:
                self.scan.unchecked.append(line)

    def _use(self, value, kind: str, shape: str, call: ast.Call, name: str | None) -> None:
        if self.learning is not None:
            return
        where = f"{self.shown}:{call.lineno}"
        if kind == "uart":
            self.scan.uses.append(PinUse(f"uart{value}", shape.format(value), where, name, kind))
        elif kind == "adc_id" and self.family == "rp2" and value in RP2_ADC_GPIO:
            gpio = RP2_ADC_GPIO[value]
            self.scan.uses.append(PinUse(str(gpio), f"{shape.format(value)} (GP{gpio})", where, name, "adc"))
        elif kind == "adc_id" and self.family == "rp2" and value == 4:
            return  # the temperature sensor: no pin
        else:
            kind = "adc" if kind == "adc_id" else kind
            self.scan.uses.append(PinUse(str(value), shape.format(value), where, name, kind))
