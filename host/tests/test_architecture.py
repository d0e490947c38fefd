"""The house in layers (docs/architecture.md): host/ imports only go down, and no class
outgrows about 300 lines."""

import ast
from pathlib import Path

from host.core.paths import REPO

LAYERS = {
    "host.core": 0,
    "host.shim": 0,  # the codec both ends share (MicroPython side, imported as data here)
    "host.link": 1,
    "host.artefacts": 2,
    "host.rig": 3,
    "host.wokwi": 3,  # a Wokwi project as a rig (host.rig.apps reads one by its path)
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
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
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
            for node in ast.walk(ast.parse(path.read_text(), str(path))):
                if isinstance(node, ast.ClassDef) and node.end_lineno - node.lineno + 1 > MAX_CLASS_LINES:
                    big.append(f"{path.relative_to(REPO)}: {node.name} has {node.end_lineno - node.lineno + 1} lines")
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
            for node in ast.walk(ast.parse(path.read_text(), str(path))):
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
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            call = isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
            if call and node.func.id in ("getattr", "hasattr"):
                subject = ast.unparse(node.args[0]) if node.args else ""
                if "plant" in subject.lower():
                    probes.append(f"{path.relative_to(REPO)}:{node.lineno}: {ast.unparse(node)}")
            elif isinstance(node, ast.Constant) and node.value == "inner" and not module.startswith("host.link"):
                probes.append(f"{path.relative_to(REPO)}:{node.lineno}: the string 'inner'")
    assert not probes, "the plant probed instead of asked:\n" + "\n".join(probes)
