"""The shim compiled once (host/core/shimcache.py): loaded as .mpy files from a folder
keyed by its content, it gives the same link trace as the source folder, an interpreter
not of our builds gets the source, and two makers at once leave one whole folder."""

import os
import threading
import time
from pathlib import Path

import pytest

from host.core import interpreter, paths, shimcache

pytestmark = pytest.mark.hil


def _ours() -> Path:
    program = interpreter.find()
    folder = shimcache.folder(program)
    if folder == paths.SHIM_DIR:
        pytest.skip(f"{program} is not one of our builds (no mpy-cross of its source): the shim is read as source")
    return program


def test_every_shim_module_is_compiled_under_its_own_folders_name():
    folder = shimcache.folder(_ours())
    sources = {p.stem for p in paths.SHIM_DIR.glob("*.py")}
    compiled = {p.stem for p in folder.glob("*.mpy")}
    assert compiled == sources, f"expected every shim module compiled in {folder}, missing {sources - compiled}"
    assert folder.parent == shimcache.cache_root(), folder


@pytest.mark.parametrize(
    ("app", "world", "seed", "cpu"),
    [("rover", "room", 3, "free"), ("duct", "multi-branch", 2, "esp32@240MHz")],
    ids=["rover", "duct-mcu-time"],
)
def test_the_compiled_shim_gives_the_same_link_trace_as_its_source(make_rig, monkeypatch, app, world, seed, cpu):
    """What the shim does cannot depend on how it was loaded: the link trace, byte for byte,
    from the compiled folder and from the source folder; with MCU time on too (the duct
    robot's multi-branch run, whose charged time a change of the shim's own objects once
    moved: docs/mcu-time.md, "The collector's pause")."""
    from host.rig.config.apps import get_app

    _ours()
    monkeypatch.setenv("MPYFIL_CPU", cpu)

    def digest():
        rig = make_rig(app, seed=seed, plant_options=dict(get_app(app).worlds[world]), trace=True)
        rig.run_for(2.0 if cpu == "free" else 4.0)
        rig.stop()
        return rig.trace_digest, rig.artefacts

    compiled = digest()
    monkeypatch.setenv(shimcache.SOURCE_ENV, "1")
    source = digest()
    assert compiled[0] == source[0], (
        f"expected one link trace from the compiled shim and from its source, got {compiled[0]} "
        f"({compiled[1]}) and {source[0]} ({source[1]})"
    )


def test_an_interpreter_not_of_our_builds_reads_the_shim_as_source(tmp_path):
    other = tmp_path / "micropython"
    other.write_text("#!/bin/sh\necho 'MicroPython v9.9.9 on 2030-01-01'\necho 2822\n")
    other.chmod(0o755)
    assert shimcache.folder(other) == paths.SHIM_DIR


def test_two_makers_at_once_leave_one_whole_folder_and_nothing_else(tmp_path):
    program = _ours()
    stamp = shimcache._sources_stamp()
    results = []

    def make(n):
        results.append(shimcache._compiled.__wrapped__(str(program), n, stamp, tmp_path))

    threads = [threading.Thread(target=make, args=(n,)) for n in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len(set(results)) == 1 and results[0] is not None, results
    left = sorted(p.name for p in tmp_path.iterdir())
    assert left == [results[0].name], f"expected only the compiled folder in {tmp_path}, got {left}"


def test_a_new_folder_takes_away_those_made_over_a_week_ago(tmp_path):
    program = _ours()
    old, recent = tmp_path / "0123456789abcdef", tmp_path / "fedcba9876543210"
    for folder in (old, recent):
        folder.mkdir()
        (folder / "_hilboot.mpy").write_bytes(b"M")
    week = shimcache.STALE_S + 60
    os.utime(old, (time.time() - week, time.time() - week))
    made = shimcache._compiled.__wrapped__(str(program), 0, shimcache._sources_stamp(), tmp_path)
    left = sorted(p.name for p in tmp_path.iterdir())
    assert left == sorted([made.name, recent.name]), f"expected {old.name} gone and {recent.name} kept, got {left}"
