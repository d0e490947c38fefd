"""Packaging (with pyproject.toml): the harness's modules, and what it runs as package data.

The wheel carries, beside ``host`` and ``sim_plant``, our firmware (apps, board pin maps,
``firmware/lib`` drivers) as ``host/_data/firmware``, the examples as
``host/_data/examples`` and the documentation (``docs/*.md``) as ``host/_data/docs``:
``host.core.paths`` and ``host.core.docs`` (``mpy-fil docs``) find them there when the
package is installed, and at the repository's top level in a checkout. The README is the
package's description (pyproject.toml). The tests stay out.
"""

from setuptools import find_packages, setup

BUNDLED = {"host._data.firmware": "firmware", "host._data.examples": "examples", "host._data.docs": "docs"}
SOURCES = ["*.py", "*.toml", "*.json"]  # what a firmware folder and a rig are made of

setup(
    packages=find_packages(include=["host*", "sim_plant*"], exclude=["*.tests", "*.tests.*"]) + list(BUNDLED),
    package_dir=BUNDLED,
    include_package_data=False,  # (only what package_data names: not the tests under host/)
    package_data={
        "host._data.firmware": [f"{d}/**/{p}" for d in ("apps", "boards", "lib") for p in SOURCES],
        "host._data.examples": [f"**/{p}" for p in SOURCES],
        "host._data.docs": ["*.md"],  # (mpy-fil docs; every docs/NAME.md a message names)
        "host.core": ["micropython/manifest.py", "micropython/*.patch", "*.sh"],
        "host.device": ["vrepl/*.py"],
        "host.conformance": ["*.toml", "bench/*.py"],
        "host.kits": ["*/*.toml", "*/*.py"],  # (each kit: kit.toml, rig.toml, test.py)
        "host.shim": ["*.py", "cmod/*/*.c", "cmod/*/*.mk"],  # (cmod: the C hot path, built in)
    },
)
