"""Each app's link trace, byte for byte: a few virtual seconds of every world of its rig
file at a fixed seed give the digest recorded before its plant was rebuilt from the parts
catalogue (a robot described part by part must do exactly what its plant class did).

The trace names the plant's class in its header and each pin's signal in its CFG records:
a robot built from parts is a ``PartsPlant``, and a part's signals are ``<name>.<signal>``
(the rover's ``bumper`` is ``bumper.out``). ``RENAMED`` lists those names per app; the
trace, with them put back, must give the digest recorded before. Anything else that
changes is a changed behaviour: record a new value only with the reason in the commit
and the app's doc page."""

import hashlib
from pathlib import Path

import pytest

from host.core.paths import REPO
from host.rig.apps import get_app

pytestmark = pytest.mark.hil

RUN_S = 4.0
SEED = 11
PICO_BOT = str(Path(REPO, "examples", "pico_bot", "rig.toml"))

DIGESTS = {  # (app, world): sha256 of the link trace
    ("rover", "room"): "7512e8f0f0a053ee2d0ccece27a18be236e6274ca7d70ae4f5f967a4be148b7c",
    ("rover", "long-room"): "079f4beb8edcbf18acd8abe4caaf34d8f6d4bbf88616e174951119c76f726c14",
    ("rover", "small-room"): "0b4f56bf16957202875b8ef5bee26dc6300eb6fc6c244d61812b27a7135a1090",
    ("vacuum", "vacuum-room"): "cb901ce034c71bf97630d0723557aaa4170c8b5aeaa1458ad6520345e7475ee8",
    ("vacuum", "open-floor"): "a31a3c3643edffcf0944db36acb08d87c0427785876e554054411f96dfe9cc1e",
    ("lab_robot", "arena"): "a642289a67569e017cd558ebcba7cfb8f10ef9679bf228fe3e04fcf5bb5b4780",
    ("lab_robot", "arena-noisy"): "59f5e1d34de2f8f0cbf3e8adf0f8884c54a8381ea695a77c0f14739e823540c6",
    ("lab_robot_canyon", "canyon"): "d71c7160a97030f305e3b143b3eaf3047a3ebbd898725f45819ea2e0934f1892",
    ("lab_robot_canyon", "canyon-noisy"): "b3ab927af55b881994cb40f254e4fc3c21f0d8ef2481be12e2a215181747b73c",
    ("pico_bot", "box-ahead"): "c4539b03e493daef0feacd14eccd98f21258b8f4e3b1bbba448fc9a7264ffd28",
    ("pico_bot", "open-room"): "bf2067b1463aebb844f845d1916158defe508d3e42316e95731d02d22e80fb68",
}

RENAMED = {  # app: (its plant class before, {signal now: signal before})
    "rover": ("RoverRoom", {"bumper.out": "bumper"}),
    "vacuum": ("VacuumRobot", {"enc_l.out": "enc_l", "enc_r.out": "enc_r"}),
    "pico_bot": ("TwoWheelRobot", {"start.out": "button.start"}),
}


def digest_before(trace: bytes, app: str) -> str:
    """The digest of ``trace`` with the names ``RENAMED`` lists put back as they were."""
    if app not in RENAMED:
        return hashlib.sha256(trace).hexdigest()
    plant, signals = RENAMED[app]
    lines = trace.decode().splitlines(keepends=True)
    lines[0] = lines[0].replace('"plant":"PartsPlant"', f'"plant":"{plant}"', 1)
    for i, line in enumerate(lines):
        if '"msg":"CFG"' in line:
            for now, before in signals.items():
                lines[i] = lines[i].replace(f'"signal":"{now}"', f'"signal":"{before}"')
    return hashlib.sha256("".join(lines).encode()).hexdigest()


@pytest.mark.parametrize(("app", "world"), sorted(DIGESTS), ids=[f"{a}-{w}" for a, w in sorted(DIGESTS)])
def test_link_trace_is_unchanged(make_rig, app, world):
    name = PICO_BOT if app == "pico_bot" else app
    options = get_app(name).worlds[world]
    rig = make_rig(name, seed=SEED, plant_options=dict(options), trace=True)
    rig.run_for(RUN_S)
    rig.stop()
    trace = (rig.artefacts / "trace.jsonl").read_bytes()
    assert hashlib.sha256(trace).hexdigest() == rig.trace_digest, "the digest is the trace file's"
    got = digest_before(trace, app)
    assert got == DIGESTS[app, world], f"{app} in {world}: the link trace changed to {got} ({rig.artefacts})"
