"""Packaging (with pyproject.toml): the harness's modules, and what it runs as package data.

The wheel installs the harness under one package of its own, ``mpy_fil``: ``host`` and
``sim_plant`` as ``mpy_fil.host`` and ``mpy_fil.sim_plant``, so that a user's repository
keeps folders of those common names (docs/architecture.md, "Installed: one package").
The checkout keeps them at the top level: the build copies them under ``mpy_fil/`` and
rewrites their imports of each other (``from host.x import y`` -> ``from mpy_fil.host.x
import y``, :func:`namespaced`) and the entry points; an editable install is the checkout
as it is. The wheel carries, beside them, our firmware (apps, board pin maps,
``firmware/lib`` drivers) as ``host/_data/firmware``, the examples as
``host/_data/examples`` and the documentation (``docs/*.md``) as ``host/_data/docs``:
``host.core.paths`` and ``host.core.docs`` (``mpy-fil docs``) find them there when the
package is installed, and at the repository's top level in a checkout. The README is the
package's description (pyproject.toml). The tests stay out.
"""

import re
import shutil
from pathlib import Path

from setuptools import find_packages, setup
from setuptools.command.bdist_wheel import bdist_wheel
from setuptools.command.build_py import build_py

NAMESPACE = "mpy_fil"
TOP = ("host", "sim_plant")
IMPORT = re.compile(r"^(\s*)(from|import)(\s+)(host|sim_plant)(?=[.\s])", re.MULTILINE)
"""An import statement of one of ours (every one starts its line: ruff's isort keeps them so)."""
ENTRY = re.compile(r"(=\s*)(host|sim_plant)(?=[.:])")


def namespaced(text: str) -> str:
    """A module's text with its imports of ours under ``mpy_fil``."""
    return IMPORT.sub(rf"\1\2\3{NAMESPACE}.\4", text)


class NamespacedBuild(build_py):
    """build_py, then ``host`` and ``sim_plant`` moved under ``mpy_fil/``, imports rewritten
    (the firmware, examples and docs under ``host/_data`` are data: left as they are)."""

    def run(self):
        super().run()
        if self.editable_mode:
            return
        lib = Path(self.build_lib)
        for top in TOP:
            target = lib / NAMESPACE / top
            shutil.rmtree(target, ignore_errors=True)
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.move(lib / top, target)
        (lib / NAMESPACE / "__init__.py").write_text('"""mpy-fil: mpy_fil.host (the harness), mpy_fil.sim_plant."""\n')
        for path in (lib / NAMESPACE).rglob("*.py"):
            if "_data" not in path.relative_to(lib / NAMESPACE).parts:
                path.write_text(namespaced(path.read_text()))


class NamespacedWheel(bdist_wheel):
    """bdist_wheel with the entry points (the ``mpy-fil`` script, the pytest plugin) under
    ``mpy_fil``. Only when it builds a wheel (run): an editable install's metadata comes
    from egg2dist too (setuptools' dist_info), and the checkout keeps its own names."""

    building = False

    def run(self):
        self.building = True
        super().run()

    def egg2dist(self, egginfo_path, distinfo_path):
        super().egg2dist(egginfo_path, distinfo_path)
        if not self.building:
            return
        entry_points = Path(distinfo_path) / "entry_points.txt"
        if entry_points.is_file():
            entry_points.write_text(ENTRY.sub(rf"\1{NAMESPACE}.\2", entry_points.read_text()))
        top_level = Path(distinfo_path) / "top_level.txt"
        if top_level.is_file():
            top_level.write_text(NAMESPACE + "\n")


BUNDLED = {"host._data.firmware": "firmware", "host._data.examples": "examples", "host._data.docs": "docs"}
SOURCES = ["*.py", "*.toml", "*.json"]  # what a firmware folder and a rig are made of

setup(
    cmdclass={"build_py": NamespacedBuild, "bdist_wheel": NamespacedWheel},
    packages=find_packages(include=["host*", "sim_plant*"], exclude=["*.tests", "*.tests.*"]) + list(BUNDLED),
    package_dir=BUNDLED,
    include_package_data=False,  # (only what package_data names: not the tests under host/)
    package_data={
        "host._data.firmware": [f"{d}/**/{p}" for d in ("apps", "boards", "lib") for p in SOURCES],
        "host._data.examples": [f"**/{p}" for p in SOURCES],
        "host._data.docs": ["*.md"],  # (mpy-fil docs; every docs/NAME.md a message names)
        "host.core": ["micropython/manifest.py", "micropython/*.patch", "micropython/*/*.patch", "*.sh"],
        "host.device": ["vrepl/*.py"],
        "host.conformance": ["*.toml", "bench/*.py"],
        "host.kits": ["*/*.toml", "*/*.py"],  # (each kit: kit.toml, rig.toml, test.py)
        "host.shim": ["*.py", "cmod/*/*.c", "cmod/*/*.mk"],  # (cmod: the C hot path, built in)
    },
)
