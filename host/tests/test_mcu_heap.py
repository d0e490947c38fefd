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


def _probe(folder, pad: int, probe: str = PROBE, harness_text: str = HARNESS) -> dict:
    harness = folder / "shim"  # (the harness's own folder, exempt as the shim's is)
    harness.mkdir(parents=True)
    (harness / "harness.py").write_text(harness_text)
    cpu = "rp2040@125MHz"
    script = probe.replace("HARNESS", repr(str(harness) + "/")).replace("PAD", str(pad))
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


# The firmware hands the harness's module what it made (as it hands the shim a buffer to write)
# and calls it at every step; the harness's module (``KEEPING``) keeps the last of them, calls
# deeper before it returns (its frames on the C stack) and opens and drops a file (an object
# with a finaliser, which the interpreter's collector runs when it finds it dead), or does
# none of it (``PLAIN``).
HANDING = PROBE.replace("    harness.churn(i, PAD)\n", "    harness.take(s, i)\n")
PLAIN = """
def hold(pad):
    pass

def take(obj, i):
    pass
"""
KEEPING = """
kept = []

def hold(pad):
    pass

def deeper(n, obj, i):
    if n:
        return deeper(n - 1, [obj, i], i)
    kept.append(obj)
    if len(kept) > 8:
        kept.pop(0)
    if i % 50 == 0:
        open(__file__)  # (dropped: the collector that finds it dead closes it)

def take(obj, i):
    deeper(1 + i % 23, obj, i)
"""


def test_what_the_harness_keeps_finalises_or_calls_changes_nothing_in_the_firmwares_counts(tmp_path):
    """The board's collector counts the firmware's blocks reachable from its own roots (its
    frames, its modules, what the shim holds for it as a board's C does), not the harness's
    modules, frames or C stack; the finalisers the interpreter's collector runs are not the
    firmware's work. So a harness's module that keeps what the firmware handed it, calls deeper
    and leaves files to be finalised gives the firmware the same counts as one that does
    none of it: its collections, the bytes in use at each, its calls into C."""
    plain = _probe(tmp_path / "plain", 0, HANDING, PLAIN)
    keeping = _probe(tmp_path / "keeping", 0, HANDING, KEEPING)
    assert plain["collects"] >= 2, f"expected the firmware's allocations to need collections, got {plain}"
    assert keeping == plain, (
        "expected the same counts whatever the harness's module keeps, finalises or calls; got"
        f" {keeping} with one that keeps, against {plain}"
    )


def test_the_modelled_heap_is_the_boards_at_this_builds_size_or_the_rig_files():
    """The firmware's collections are scheduled in its board's heap: the family's (HEAPS) at
    64-bit objects, twice a board's bytes, or the rig file's heap_size when it names one."""
    told = mcutime.shim_settings("rp2040@125MHz")
    assert told["cpu_heap"] == 2 * mcutime.HEAPS["rp2040"], told["cpu_heap"]
    told = mcutime.shim_settings("esp32@240MHz", 96 * 1024)
    assert told["cpu_heap"] == 96 * 1024, told["cpu_heap"]
    board = mcutime.CPUS["esp32@240MHz"]
    own = dataclasses.replace(board, heap=96 * 1024 // mcutime.WORD_RATIO).table()
    assert told["cpu_cost"] == own != board.table(), "expected the sweep to cost the rig file's heap"
    assert mcutime.shim_settings(mcutime.FREE, 96 * 1024) == {}, "a free CPU models no heap"


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


def _run_in_checkout(root, app: str, world: str, seed: int, seconds: float, cpu: str, shim: dict | None = None) -> str:
    """The run's trace digest from a copy of the tree at ``root``, with ``shim``'s text appended
    to the shim's modules it names (a module name: text)."""
    ignore = shutil.ignore_patterns("__pycache__", "build", "*.pyc")
    for name in TREE:
        src = REPO / name
        if src.is_dir():
            shutil.copytree(src, root / name, ignore=ignore)
        else:
            shutil.copy2(src, root / name)
    for module, text in (shim or {}).items():
        path = root / "host" / "shim" / f"{module}.py"
        path.write_text(path.read_text() + textwrap.dedent(text))
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


def shim_change(pad: int, depth: int) -> dict:
    """The shim's ``_hil`` with ``pad`` more objects held from its import and its clock syncs
    through ``depth`` more frames of its own, which allocate on the way and keep some of it."""
    return {
        "_hil": f"""
        _extra = [bytearray(64) for _ in range({pad})]
        _extra_kept = []


        def _extra_deeper(sync, depth):
            def deeper(n, t_target, watch):
                if n:
                    junk = [n] * 8
                    if n % 5 == 0:
                        _extra_kept.append(bytearray(n))
                        del _extra_kept[:-40]
                    return deeper(n - 1, t_target, watch) or junk is None
                return sync(t_target, watch)

            return lambda t_target, watch: deeper(depth, t_target, watch)


        _released_run_until = _extra_deeper(_released_run_until, {depth})
    """
    }


SHIM_CHANGES = ((300, 20), (37, 3))
"""Changes of the shim's own work only (:func:`shim_change`): more objects, deeper frames,
garbage. The firmware sees the same shim (what it calls does and returns the same). Two of
them: whether one moved a trace before depended on where the heap's blocks fell (the tree's
path too)."""


@pytest.mark.parametrize(("app", "world", "seed", "seconds"), [("duct", "multi-branch", 2, 4.0)])
def test_a_change_of_the_shims_own_work_leaves_the_trace_with_mcu_time_unchanged(tmp_path, app, world, seed, seconds):
    """The same firmware gets the same charged time whatever the shim does internally
    (docs/mcu-time.md, "The collector's pause"): the duct robot's multi-branch run with MCU time
    on gives one trace from the tree as it is and from ones whose shim does more of its own work
    (SHIM_CHANGES). (Before the collector's finalisers were the interpreter's, and its count of
    the firmware's blocks in use the board's, the second read a sample 45 us earlier at 1.48 s.)"""
    cpu = "esp32@240MHz"
    plain = _run_in_checkout(tmp_path / "plain", app, world, seed, seconds, cpu)
    for pad, depth in SHIM_CHANGES:
        root = tmp_path / f"changed-{pad}-{depth}"
        changed = _run_in_checkout(root, app, world, seed, seconds, cpu, shim_change(pad, depth))
        assert changed == plain, (
            f"{app} in {world}, seed {seed}, cpu {cpu}: expected the same trace with the shim holding {pad}"
            f" objects more and syncing {depth} frames deeper, got {changed} against {plain}"
            f" (traces: {tmp_path / 'plain' / 'out'}, {root / 'out'})"
        )
