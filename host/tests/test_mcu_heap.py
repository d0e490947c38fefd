"""MCU time's collector and allocations (docs/mcu-time.md, "The collector's pause"): what the
firmware is charged for its heap does not depend on what the harness holds in the same
heap (the shim's objects, the host paths of its source) or on where in the heap a block
lies; so a trace with MCU time on is the same in a checkout at any path."""

import dataclasses
import hashlib
import json
import os
import shutil
import subprocess
import sys
import textwrap

import pytest

from host.core import interpreter
from host.core.paths import REPO
from host.rig.targets import mcutime

# A firmware step that allocates (garbage, a list that grows: a realloc in place or moved, by
# what lies after it) and keeps some; between steps the harness's module allocates and keeps
# ``PAD`` bytes more or less (as the shim's host paths are longer or shorter).
PROBE = """
import _hilfast, binascii, json, harness

_hilfast.exempt(HARNESS)
harness.hold(PAD)
_hilfast.cost(binascii.unhexlify(TABLE), HEAP)
c0 = _hilfast.counts()
log, kept = [], []
for i in range(12000):
    log.append(i)
    s = bytearray(40 + i % 50)
    if i % 40 == 0:
        kept.append(bytes(s))
    harness.churn(i, PAD)
    if len(log) > 700:
        log = []
c1 = _hilfast.counts()
d = {k: c1[k] - c0[k] for k in c1 if k != "ops"}
d["ops"] = sum(c1["ops"]) - sum(c0["ops"])
d["owed_us"] = _hilfast.owed_us()
print(json.dumps(d))
"""
HARNESS = """
held = []

def hold(pad):
    held.append("/" * pad + "host/shim/_hil.py")

def churn(i, pad):
    if i % 7 == 0:
        held.append(bytearray(1 + (i * pad) % 97))
    return [i] * (1 + pad % 13)
"""


def _probe(folder, pad: int) -> dict:
    harness = folder / "shim"  # (the harness's own folder, exempt as the shim's is)
    harness.mkdir(parents=True)
    (harness / "harness.py").write_text(HARNESS)
    cpu = "rp2040@125MHz"
    script = PROBE.replace("HARNESS", repr(str(harness) + "/")).replace("PAD", str(pad))
    script = script.replace("TABLE", repr(mcutime.CPUS[cpu].table().hex()))
    script = script.replace("HEAP", str(mcutime.heap_model(cpu)))
    (folder / "probe.py").write_text(script)
    env = {**os.environ, "MICROPYPATH": f"{harness}:.frozen"}
    out = subprocess.run(
        [str(interpreter.find()), str(folder / "probe.py")], capture_output=True, text=True, timeout=60, env=env
    )
    assert out.returncode == 0, f"expected the probe to run, got {out.returncode}: {out.stderr} ({folder})"
    return json.loads(out.stdout)


def test_what_the_harness_holds_changes_nothing_in_the_firmwares_counts(tmp_path):
    """The firmware's allocations (a growth counted the same whether it moved or not), its
    collections (the board's heap, scheduled by its own allocations) and the bytes in use at
    each (its own blocks) are the same whatever the harness's module allocates beside it."""
    runs = {pad: _probe(tmp_path / f"pad{pad}", pad) for pad in (0, 37, 4000)}
    first = runs[0]
    assert first["collects"] >= 2, f"expected the firmware's allocations to need collections, got {first}"
    assert first["gc_used_bytes"] > 0, f"expected the firmware's kept objects in use at them, got {first}"
    for pad, got in runs.items():
        assert got == first, f"the harness holding {pad} bytes more changed the firmware's counts: {got} vs {first}"


def test_the_modelled_heap_is_the_boards_at_this_builds_size_or_the_rig_files():
    """The firmware's collections are scheduled in its board's heap: the family's (HEAPS) at
    64-bit objects, twice a board's bytes, or the rig file's heap_size when it names one."""
    env = mcutime.shim_env("rp2040@125MHz")
    assert env["HIL_CPU_HEAP"] == str(2 * mcutime.HEAPS["rp2040"]), env["HIL_CPU_HEAP"]
    env = mcutime.shim_env("esp32@240MHz", 96 * 1024)
    assert env["HIL_CPU_HEAP"] == str(96 * 1024), env["HIL_CPU_HEAP"]
    board = mcutime.CPUS["esp32@240MHz"]
    own = dataclasses.replace(board, heap=96 * 1024 // mcutime.WORD_RATIO).table().hex()
    assert env["HIL_CPU_COST"] == own != board.table().hex(), "expected the sweep to cost the rig file's heap"
    assert mcutime.shim_env(mcutime.FREE, 96 * 1024) == {}, "a free CPU models no heap"


TREE = ("host", "firmware", "sim_plant", "pyproject.toml")
"""What a checkout needs to run a rig (host.core.paths.CHECKOUT: pyproject.toml, firmware/)."""
RUN = """
import hashlib, sys
from pathlib import Path
from host.pytest_plugin import rig_from_keywords
from host.rig.config.apps import get_app
app, world, seed, seconds, out = sys.argv[1:]
spec = dict(get_app(app).worlds[world])
rig = rig_from_keywords(app, seed=int(seed), plant_options=spec, trace=True, artefacts=Path(out))
rig.start()
rig.run_for(float(seconds))
rig.stop()
print(hashlib.sha256((rig.artefacts / "trace.jsonl").read_bytes()).hexdigest())
"""


def _run_in_checkout(root, app: str, world: str, seed: int, seconds: float, cpu: str) -> str:
    ignore = shutil.ignore_patterns("__pycache__", "build", "*.pyc")
    for name in TREE:
        src = REPO / name
        if src.is_dir():
            shutil.copytree(src, root / name, ignore=ignore)
        else:
            shutil.copy2(src, root / name)
    env = {**os.environ, "PYTHONPATH": str(root), "MPYFIL_CPU": cpu, "MICROPYTHON": str(interpreter.find())}
    env.pop("PYTHONPYCACHEPREFIX", None)
    out = subprocess.run(
        [sys.executable, "-c", textwrap.dedent(RUN), app, world, str(seed), str(seconds), str(root / "out")],
        capture_output=True,
        text=True,
        timeout=300,
        cwd=root,
        env={**env, "PYTHONDONTWRITEBYTECODE": "1"},
    )
    assert out.returncode == 0, f"expected the rig to run in the checkout {root}, got: {out.stderr[-2000:]}"
    return out.stdout.split()[-1]


@pytest.mark.parametrize(("app", "world", "seed", "seconds"), [("duct", "bench", 1, 3.0)])
def test_checkouts_at_paths_of_other_lengths_give_the_same_trace_with_mcu_time(tmp_path, app, world, seed, seconds):
    """The duct robot on its ESP32's CPU from three copies of the tree whose paths differ in
    length by 7 and 14 bytes (the shim's source paths are in the interpreter's heap, and so
    where the firmware's objects lie): one trace. (Before the collector was modelled and a
    growth counted the same in place or moved, these three gave three traces.)"""
    cpu = "esp32@240MHz"
    roots = [tmp_path / ("a" + "b" * n) for n in (0, 7, 14)]
    digests = [_run_in_checkout(root, app, world, seed, seconds, cpu) for root in roots]
    assert hashlib.sha256(b"").hexdigest() not in digests, f"expected a trace, got an empty file ({roots[0] / 'out'})"
    for root, digest in zip(roots[1:], digests[1:]):
        assert digest == digests[0], (
            f"{app} in {world}, seed {seed}, cpu {cpu}: the trace's digest is {digests[0]} from {roots[0]} and"
            f" {digest} from {root} (traces: {roots[0] / 'out'}, {root / 'out'})"
        )
