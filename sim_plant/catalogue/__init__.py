"""The catalogue of parts, bodies, worlds, report views and campaign judges a rig is built
from and judged by (``[plant] body = ...``, ``[[plant.parts]]``, ``world = ...``, ``[report]
views``, ``[campaign] judge``; ``docs/parts.md``, ``docs/own-parts.md``).

Every module of this package is looked at: a module that declares a
:class:`~sim_plant.catalogue.base.PartType`, ``BodyType``, ``WorldType``, ``ReportView`` or
``Judge`` subclass with a ``kind`` is an entry, one class per module. Adding a part is
adding its module (and its test): nothing else names it.

A user's own entries are found the same way, from outside this package:

- a rig file's ``[plant] catalogue = ["parts/", "mybot.parts"]``: folders (relative to
  the rig file; each module in one is looked at, a module without an entry is a helper)
  and importable modules (:func:`add`);
- a ``kind`` (``body``, ``world``, a judge) written ``"module:Class"`` (:func:`resolve`);
- the entry-point group ``mpy_fil.catalogue`` of any installed package, each entry a
  module (or package) looked at as a folder is, or one class.
"""

import functools
import hashlib
import importlib
import importlib.util
import pkgutil
import sys
from pathlib import Path

from sim_plant.catalogue.base import BodyType, Judge, PartsError, PartType, ReportView, WorldType

NOT_ENTRIES = frozenset(("base", "assembly", "docs", "imu"))  # (imu: the IMU chips' shared model and part)
ENTRY_POINT_GROUP = "mpy_fil.catalogue"
TABLES = {"parts": PartType, "bodies": BodyType, "worlds": WorldType, "views": ReportView, "judges": Judge}
"""Each table and the class its entries derive from."""
_added: dict[str, tuple] = {}
"""A source added by :func:`add` (a folder's resolved path, a module's name) -> its modules."""


def _declared(module) -> list[type]:
    return [
        obj
        for obj in vars(module).values()
        if isinstance(obj, type)
        and obj.__module__ == module.__name__
        and issubclass(obj, tuple(TABLES.values()))
        and obj.kind
    ]


def _table_of(cls) -> str:
    return next(name for name, base in TABLES.items() if issubclass(cls, base))


def _put(tables: dict, cls, where: str) -> None:
    table = tables[_table_of(cls)]
    if cls.kind in table and table[cls.kind] is not cls:
        raise TypeError(f"{where}: kind {cls.kind!r} is {table[cls.kind].__module__}'s too")
    table[cls.kind] = cls


@functools.cache
def _ours() -> dict:
    tables = {name: {} for name in TABLES}
    for info in sorted(pkgutil.iter_modules(__path__), key=lambda i: i.name):
        if info.name in NOT_ENTRIES:
            continue
        package = importlib.import_module(f"{__name__}.{info.name}")
        for module in _modules_of(package)[1:] if info.ispkg else [package]:  # (places/: a module a world)
            found = _declared(module)
            if len(found) != 1:
                raise TypeError(f"{module.__name__}: expected one catalogue class with a kind, got {found}")
            _put(tables, found[0], module.__name__)
    return tables


def _modules_of(module) -> list:
    """A module, or a package and its modules."""
    found = [module]
    for info in pkgutil.iter_modules(getattr(module, "__path__", ())):
        found.append(importlib.import_module(f"{module.__name__}.{info.name}"))
    return found


@functools.cache
def _installed() -> tuple:
    """The classes the entry-point group names, with where each came from."""
    import importlib.metadata  # (here: 0.05 to 0.1 s to import, paid only when a kind is not ours)

    classes = []
    for ep in sorted(importlib.metadata.entry_points(group=ENTRY_POINT_GROUP), key=lambda e: e.name):
        where = f"entry point {ep.name} = {ep.value!r} ({ENTRY_POINT_GROUP})"
        try:
            obj = ep.load()
        except Exception as e:  # (someone else's package: named, not a traceback)
            raise PartsError(f"{where}: cannot be loaded: {type(e).__name__}: {e}") from None
        if isinstance(obj, type):
            classes.append((obj, where))
        else:
            classes += [(cls, where) for m in _modules_of(obj) for cls in _declared(m)]
    return tuple(classes)


def _entries() -> dict:
    tables = {name: dict(table) for name, table in _ours().items()}
    for cls, where in _installed():
        _put(tables, cls, where)
    for source, modules in _added.items():
        for module in modules:
            for cls in _declared(module):
                _put(tables, cls, f"{source} ({module.__name__})")
    return tables


def _load_folder(folder: Path) -> tuple:
    """Every module of a folder, imported as the modules of a package of its own (so they
    import each other as ``from .common import x``); the package's name is the folder's
    hash, never a name of the user's own."""
    name = "_mpy_fil_own_" + hashlib.sha256(str(folder).encode()).hexdigest()[:12]
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(
            name, folder / "__init__.py", submodule_search_locations=[str(folder)]
        )
        package = importlib.util.module_from_spec(spec)
        sys.modules[name] = package
        if (folder / "__init__.py").is_file():
            spec.loader.exec_module(package)
    return tuple(
        importlib.import_module(f"{name}.{info.name}")
        for info in sorted(pkgutil.iter_modules([str(folder)]), key=lambda i: i.name)
    )


def add(source: str, base: Path | None = None) -> tuple:
    """Add a user's source of entries: a folder (``parts/``, relative to ``base``, the rig
    file's folder) or an importable module or package name; (the source as an absolute
    folder or the module's name, its modules), imported once."""
    if not isinstance(source, str) or not source:
        raise PartsError(f"[plant] catalogue: expected a folder or a module name, got {source!r}"[:200])
    folder = (Path(base or ".") / source).resolve()
    if source.endswith("/") or "/" in source or folder.is_dir():
        if not folder.is_dir():
            raise PartsError(f"[plant] catalogue: no folder {folder}")
        key = str(folder)
        if key not in _added:
            _take(key, _load_folder(folder))
        return key, _added[key]
    if source not in _added:
        try:
            module = importlib.import_module(source)
        except ImportError as e:
            raise PartsError(f"[plant] catalogue: cannot import {source!r} ({e}); a folder ends in '/'") from None
        _take(source, tuple(_modules_of(module)))
    return source, _added[source]


def _take(source: str, modules: tuple) -> None:
    """Add a source's modules; a kind already taken (ours or another source's) is refused."""
    _added[source] = modules
    try:
        _entries()
    except TypeError as e:
        del _added[source]
        raise PartsError(f"[plant] catalogue: {e}") from None


def resolve(table: str, kind) -> type | None:
    """The class of ``kind`` in ``table`` (a name in the catalogue, ours or a user's, or a
    ``"module:Class"`` reference, imported); None when there is no such entry."""
    if isinstance(kind, str) and ":" in kind:
        module_name, _, attr = kind.partition(":")
        try:
            cls = getattr(importlib.import_module(module_name), attr)
        except (ImportError, AttributeError) as e:
            raise PartsError(f"{kind!r}: cannot import it ({type(e).__name__}: {e})") from None
        if not (isinstance(cls, type) and issubclass(cls, TABLES[table])):
            raise PartsError(f"{kind!r}: expected a {TABLES[table].__name__} subclass, got {cls!r}"[:200])
        return cls
    return _ours()[table].get(kind) or _entries()[table].get(kind)


def parts() -> dict[str, type]:
    """Part kind -> its class, ours in name order, then a user's."""
    return _entries()["parts"]


def bodies() -> dict[str, type]:
    """Body kind -> its class."""
    return _entries()["bodies"]


def worlds() -> dict[str, type]:
    """World kind -> its class."""
    return _entries()["worlds"]


def views() -> dict[str, type]:
    """Report view name -> its class."""
    return _entries()["views"]


def judges() -> dict[str, type]:
    """Campaign judge name -> its class."""
    return _entries()["judges"]


def ours(table: str) -> dict[str, type]:
    """Only this package's entries (docs/parts.md is generated from these)."""
    return dict(_ours()[table])
