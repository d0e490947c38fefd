"""host/rig/ is split by job (docs/architecture.md); the paths users and our docs import
from keep working: ``host.rig``'s own names, and every module's path of 0.2
(``host.rig.rigfile``) as the same module as its new home (``host.rig.config.rigfile``)."""

import importlib
import subprocess
import sys

import host.rig
from host.core.paths import REPO

PUBLIC = {  # what README.md, docs/ and hil_tests/ import from host.rig, by module
    "host.rig": ["Rig", "RigSpec", "Recording"],
    "host.rig.apps": ["get_app", "apps"],
    "host.rig.boardfile": ["load_boards", "boards_from_data"],
    "host.rig.boardfs": ["PREFIX", "flash_files"],
    "host.rig.boardset": ["BoardSet"],
    "host.rig.budgets": ["Budget", "CHANGE", "COMPUTE", "LEVEL"],
    "host.rig.introspect": ["FirmwareEvalError"],
    "host.rig.messages": ["on_cfg"],
    "host.rig.migrate": ["migrate_text"],
    "host.rig.replay": ["FirmwareChoice", "replay"],
    "host.rig.rigfile": ["load_rig", "rig_from_data"],
    "host.rig.spec": ["build_plant", "fault_schedule", "placed"],
    "host.rig.target": ["FaultyLinkTarget"],
    "host.rig.tomlfile": ["read_toml"],
    "host.wokwi.project": ["rig_from_project", "is_project"],  # (now host.rig.config.wokwi.project)
}


def test_the_public_names_import_from_their_paths_of_0_2():
    missing = []
    for module, names in PUBLIC.items():
        found = importlib.import_module(module)
        missing += [f"{module}.{name}" for name in names if not hasattr(found, name)]
    assert not missing, f"names users import, expected at their paths, missing: {missing}"


def test_every_module_of_0_2_is_its_moved_module_itself():
    wrong = []
    for name, package in host.rig.MOVED.items():
        new = f"host.rig.{package}.{name}"
        if not (REPO / "host" / "rig" / package / f"{name}.py").is_file():
            wrong.append(f"{new}: no such file")
            continue
        old = importlib.import_module(f"host.rig.{name}")
        if old is not importlib.import_module(new) or old.__spec__.name != new:
            wrong.append(f"host.rig.{name}: expected the module {new}, got {old.__spec__.name}")
    assert not wrong, wrong


def test_every_wokwi_module_of_0_2_is_its_moved_module_itself():
    import host.wokwi

    for name in host.wokwi.MOVED:
        old = importlib.import_module(f"host.wokwi.{name}")
        new = importlib.import_module(f"host.rig.config.wokwi.{name}")
        assert old is new, f"host.wokwi.{name}: expected the module {new.__name__}, got {old.__spec__.name}"


def test_importing_host_rig_imports_no_module_by_its_old_path():
    """The old paths are served when asked for, never imported ahead (an import costs start-up)."""
    code = "import sys, host.rig; print(sorted(m for m in sys.modules if m.startswith('host.rig.')))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO, check=True).stdout
    old = [m for m in eval(out) if m.rpartition(".")[0] == "host.rig" and m.rpartition(".")[2] in host.rig.MOVED]
    assert not old, f"expected no module under its 0.2 path after `import host.rig`, got {old}"
