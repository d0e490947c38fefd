"""The house in layers (docs/architecture.md): host/ imports only go down, no module or
package imports itself round a cycle, and no class outgrows about 300 lines."""

import ast
import dataclasses
import functools
from pathlib import Path

from host.core.paths import REPO

LAYERS = {
    "host.core": 0,
    "host.shim": 0,  # the codec both ends share (MicroPython side, imported as data here)
    "host.link": 1,
    "host.artefacts": 2,
    "host.rig": 3,
    "host.wokwi": 3,  # the 0.2 import paths of host/rig/config/wokwi/ (a Wokwi project as a rig)
    "host.coverage": 3,  # firmware coverage: beside the rig it measures
    "host.kits": 3,  # robot kits' rig files and tests (mpy-fil init --kit)
    "host.report": 4,
    "host.device": 5,
    "host.campaign": 5,
    "host.scenario": 5,
    "host.shrink": 5,  # over campaign runs
    "host.diff": 5,
    "host.live": 5,  # a rig driven call by call (docs/live.md): over the scenario runner's pokes
    "host.cli": 6,
    "host.pytest_plugin": 6,
    "host.bench": 6,
    "host.soak": 6,
    "host.conformance": 6,
    "host.mcubench": 6,
}
MICROPYTHON_SIDE = ("host/shim", "host/device/vrepl", "host/core/micropython", "host/tests")
KIT_TESTS = "host/kits/"
MAX_CLASS_LINES = 310


@dataclasses.dataclass(frozen=True)
class Facts:
    """What the tests below read of a file, from one walk of its syntax tree: the tests share
    it (a file is parsed once a session; every tree kept whole would cost more, in the garbage
    collector's passes over them, than parsing each again)."""

    imports: tuple  # its ast.Import and ast.ImportFrom nodes, at the top or inside a function
    classes: tuple  # (name, first line, last line) of each class
    plant_probes: tuple  # (line, the probed object's source, the call's) of each getattr/hasattr
    inner_lines: tuple  # the lines of the string constant "inner"


@functools.cache
def facts(path: Path) -> Facts:
    imports, classes, probes, inner = [], [], [], []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            imports.append(node)
        elif isinstance(node, ast.ClassDef):
            classes.append((node.name, node.lineno, node.end_lineno))
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in ("getattr", "hasattr"):
            probes.append((node.lineno, ast.unparse(node.args[0]) if node.args else "", ast.unparse(node)))
        elif isinstance(node, ast.Constant) and node.value == "inner":
            inner.append(node.lineno)
    return Facts(tuple(imports), tuple(classes), tuple(probes), tuple(inner))


def layer_of(module: str) -> int | None:
    for prefix, layer in sorted(LAYERS.items(), key=lambda kv: -len(kv[0])):
        if module == prefix or module.startswith(prefix + "."):
            return layer
    return None


def host_modules():
    for path in sorted((REPO / "host").rglob("*.py")):
        rel = path.relative_to(REPO).as_posix()
        if rel.startswith(MICROPYTHON_SIDE) or rel.startswith(KIT_TESTS) and path.name == "test.py":
            continue  # (a kit's test.py is a user's test, written into their repository)
        module = rel[: -len(".py")].replace("/", ".").removesuffix(".__init__")
        yield module, path


def imported(path: Path) -> list[tuple[int, str]]:
    """Every host module a file imports, at the top or inside a function."""
    found = []
    for node in facts(path).imports:
        if isinstance(node, ast.Import):
            found += [(node.lineno, a.name) for a in node.names if a.name.startswith("host.")]
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            if node.module == "host":
                found += [(node.lineno, f"host.{a.name}") for a in node.names]
            elif node.module.startswith("host."):
                found.append((node.lineno, node.module))
    return found


def test_every_host_module_belongs_to_a_layer():
    unplaced = [module for module, _ in host_modules() if module != "host" and layer_of(module) is None]
    assert not unplaced, f"modules in no layer of docs/architecture.md: {unplaced}"


def test_host_imports_only_go_down_the_layers():
    upward = []
    for module, path in host_modules():
        mine = layer_of(module)
        for line, target in imported(path):
            theirs = layer_of(target)
            if mine is not None and theirs is not None and theirs > mine:
                where = f"{path.relative_to(REPO)}:{line}"
                upward.append(f"{where}: {module} (layer {mine}) imports {target} (layer {theirs})")
    assert not upward, "imports that go up a layer:\n" + "\n".join(upward)


def test_no_class_in_host_or_sim_plant_is_over_about_300_lines():
    big = []
    for folder in ("host", "sim_plant"):
        for path in (REPO / folder).rglob("*.py"):
            for name, first, last in facts(path).classes:
                if last - first + 1 > MAX_CLASS_LINES:
                    big.append(f"{path.relative_to(REPO)}: {name} has {last - first + 1} lines")
    assert not big, big


def test_only_the_catalogue_imports_the_physics_of_its_parts():
    """``sim_plant/physics/<kind>.py`` is the physics of one catalogue part: the catalogue
    (and the physics itself) imports it, tests may measure it alone; nothing else does."""
    strangers = []
    for folder in ("host", "sim_plant"):
        for path in sorted((REPO / folder).rglob("*.py")):
            rel = path.relative_to(REPO).as_posix()
            if rel.startswith(("sim_plant/catalogue/", "sim_plant/physics/", "sim_plant/tests/", "host/tests/")):
                continue
            for node in facts(path).imports:
                names = []
                if isinstance(node, ast.Import):
                    names = [a.name for a in node.names]
                elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                    names = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
                if any(n == "sim_plant.physics" or n.startswith("sim_plant.physics.") for n in names):
                    strangers.append(f"{rel}:{node.lineno}")
    assert not strangers, f"imports of sim_plant.physics outside the catalogue: {strangers}"


def test_the_host_asks_no_plant_what_it_has():
    """The host calls the plant's interface (sim_plant/plant.py: defaults and declared
    capabilities): no ``getattr``/``hasattr`` of a plant, no hand-unwrapping of the fault
    wrapper (``inner``: its ``unwrapped`` says)."""
    probes = []
    for module, path in host_modules():
        found = facts(path)
        for line, subject, call in found.plant_probes:
            if "plant" in subject.lower():
                probes.append(f"{path.relative_to(REPO)}:{line}: {call}")
        if not module.startswith("host.link"):
            probes += [f"{path.relative_to(REPO)}:{line}: the string 'inner'" for line in found.inner_lines]
    assert not probes, "the plant probed instead of asked:\n" + "\n".join(probes)


# ── cycles: between modules, and between packages ───────────────────────────────────────
PACKAGE_LEVELS = ({}, {"host.rig": 3})
"""Packages as the cycles are looked for: ``host.rig``, ``sim_plant.catalogue`` (the top
level under host/ and sim_plant/); then host.rig's sub-packages (``host.rig.loop``,
``host.rig.config``, ...) each as a package of its own."""
KNOWN_PACKAGE_CYCLES = {}
"""Package cycles that stay for now, each with its reason."""
KNOWN_MODULE_CYCLES = {
    frozenset({"sim_plant.catalogue", "sim_plant.catalogue.base"}): "the catalogue's registry (its __init__) "
    "holds the declarations base.py defines, and a declaration looks a part or a world up in it by name",
}
"""Module cycles inside one package that stay, each with its reason."""


def python_modules() -> dict[str, Path]:
    """Every module of host/ and sim_plant/ CPython imports (not the MicroPython side, not tests)."""
    found = {}
    for folder in ("host", "sim_plant"):
        for path in sorted((REPO / folder).rglob("*.py")):
            rel = path.relative_to(REPO).as_posix()
            if rel.startswith(MICROPYTHON_SIDE + ("sim_plant/tests",)) or "/tests/" in rel:
                continue
            if rel.startswith(KIT_TESTS) and path.name == "test.py":
                continue
            found[rel[: -len(".py")].replace("/", ".").removesuffix(".__init__")] = path
    return found


def import_graph(modules: dict[str, Path]) -> dict[str, set[str]]:
    """module -> the modules of ours it imports, at the top or inside a function
    (``from a import b`` imports ``a.b`` when that is a module, else ``a``)."""
    graph = {}
    for module, path in modules.items():
        edges = set()
        for node in facts(path).imports:
            if isinstance(node, ast.Import):
                edges |= {a.name for a in node.names}
            elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                for a in node.names:
                    edges.add(f"{node.module}.{a.name}" if f"{node.module}.{a.name}" in modules else node.module)
        graph[module] = {e for e in edges if e in modules and e != module}
    return graph


def strongly_connected(graph: dict[str, set[str]]) -> list[set[str]]:
    """Tarjan's strongly connected components with more than one member: the cycles."""
    index, low, stack, on, found, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = set()
            while True:
                w = stack.pop()
                on.discard(w)
                component.add(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(component)

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def package_of(module: str, depths: dict[str, int]) -> str:
    parts = module.split(".")
    for prefix, depth in depths.items():
        if module.startswith(prefix + ".") and len(parts) >= depth:
            return ".".join(parts[:depth])
    return ".".join(parts[:2])


def cycle_text(component: set[str], graph: dict[str, set[str]]) -> str:
    edges = sorted(f"{a} -> {b}" for a in component for b in graph.get(a, ()) if b in component)
    return f"{sorted(component)}: " + "; ".join(edges)


@functools.cache
def graphs() -> tuple[dict[str, set[str]], list[dict[str, set[str]]]]:
    """The modules' import graph, and the packages' at each of :data:`PACKAGE_LEVELS`."""
    graph = import_graph(python_modules())
    levels = []
    for depths in PACKAGE_LEVELS:
        packages: dict[str, set[str]] = {}
        for module, targets in graph.items():
            mine = package_of(module, depths)
            packages.setdefault(mine, set()).update(p for p in (package_of(t, depths) for t in targets) if p != mine)
        levels.append(packages)
    return graph, levels


def test_no_module_imports_itself_round_a_cycle():
    graph, _ = graphs()
    found = [cycle_text(c, graph) for c in strongly_connected(graph) if frozenset(c) not in KNOWN_MODULE_CYCLES]
    assert not found, "module cycles (expected none but those in KNOWN_MODULE_CYCLES):\n" + "\n".join(found)


def test_no_package_imports_itself_round_a_cycle():
    """Packages (``host.link``, ``sim_plant.catalogue``, ``host.rig.loop``, ...) import one
    another in one direction; a module imported by a function counts as one at the top."""
    found = []
    for packages in graphs()[1]:
        cycles = strongly_connected(packages)
        found += [cycle_text(c, packages) for c in cycles if frozenset(c) not in KNOWN_PACKAGE_CYCLES]
    assert not found, "package cycles (expected none but those in KNOWN_PACKAGE_CYCLES):\n" + "\n".join(found)


def test_the_cycles_listed_as_known_still_exist():
    """A cycle removed leaves the lists: what they name is what is there."""
    graph, levels = graphs()
    modules = {frozenset(c) for c in strongly_connected(graph)}
    packages = {frozenset(c) for level in levels for c in strongly_connected(level)}
    gone = [sorted(c) for c in KNOWN_MODULE_CYCLES if c not in modules]
    gone += [sorted(c) for c in KNOWN_PACKAGE_CYCLES if c not in packages]
    assert not gone, f"cycles listed as known, expected to exist, no longer found: {gone}"


def test_the_cycle_finder_finds_a_cycle_between_packages_through_a_function_level_import():
    graph = {"host.a.x": {"host.b.y"}, "host.b.y": {"host.a.z"}, "host.a.z": set(), "host.c": {"host.a.x"}}
    packages = {"host.a": {"host.b"}, "host.b": {"host.a"}, "host.c": {"host.a"}}
    assert strongly_connected(graph) == [], "expected no module cycle in a chain"
    assert strongly_connected(packages) == [{"host.a", "host.b"}], "expected host.a <-> host.b"


RIG_JOBS = ("host.rig.targets", "host.rig.scan", "host.rig.config", "host.rig.hardware", "host.rig.loop")
"""host/rig/'s sub-packages, lowest first, as docs/architecture.md draws them: each imports
only those before it."""


def test_host_rig_sub_packages_import_only_those_drawn_below_them():
    graph, _ = graphs()
    found = set(package_of(m, {"host.rig": 3}) for m in graph if m.startswith("host.rig."))
    assert found == set(RIG_JOBS), f"expected host/rig's sub-packages {RIG_JOBS}, found {sorted(found)}"
    upward = []
    for module, targets in graph.items():
        mine = package_of(module, {"host.rig": 3})
        for target in targets:
            theirs = package_of(target, {"host.rig": 3})
            if mine in RIG_JOBS and theirs in RIG_JOBS and RIG_JOBS.index(theirs) > RIG_JOBS.index(mine):
                upward.append(f"{module} ({mine}) imports {target} ({theirs})")
    assert not upward, "host.rig sub-packages importing upward:\n" + "\n".join(upward)
