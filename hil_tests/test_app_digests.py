"""Each app's link trace, byte for byte: a few virtual seconds of every world of its rig
file at a fixed seed give the digest recorded before its plant was rebuilt from the parts
catalogue (a robot described part by part must do exactly what its plant class did).

The trace names the plant's class in its header and each pin's signal in its CFG records:
a robot built from parts is a ``PartsPlant``, and a part's signals are ``<name>.<signal>``
(the rover's ``bumper`` is ``bumper.out``). ``RENAMED`` lists those names per app; the
trace, with them put back, must give the recorded digest (the pool cleaner's and the duct
robot's digests were re-recorded with the new names instead: their comments say so). The
header names the firmware folder relative to the repository, so a digest is the same in
every checkout. Anything else that changes is a changed behaviour: record a new value only
with the reason in the commit and the app's doc page (``docs/<app>.md``).

Run from a flashed board (``make hil FIRMWARE=build/vboard/<board>/fs``), the flashed app's
trace is held to the same digest with its header's firmware put back as the sources' (the
flash holds the same code as ``.mpy``: only that header entry may differ, hil_tests/flashed.py)."""

import hashlib
import os
import re
from pathlib import Path

import pytest
from flashed import as_from_sources

from host.core.paths import REPO
from host.rig.config.apps import get_app
from host.rig.scan import boards
from host.rig.targets import mcutime

pytestmark = pytest.mark.hil

SECONDS = {"pool_cleaner": 60.0, "pool_cleaner_adc": 60.0, "duct": 8.0}  # others: RUN_S
RUN_S = 4.0
APP_PATHS = {"pico_bot": str(Path(REPO, "examples", "pico_bot", "rig.toml"))}

DIGESTS = {  # (app, world of its rig file, seed): SHA-256 of the link trace after its seconds
    # Recorded before the rover, the vacuum, the lab robot and pico_bot's plants moved to the
    # parts catalogue, with the absolute firmware folder of the checkout they were taken in;
    # these are the same traces (with RENAMED's names put back) with only that path made
    # relative to the repository.
    ("rover", "room", 11): "f1c7661bcd40aeff6cfe1a84e2db6b5cf07aef466c59677a0ec5bee3c659689b",
    ("rover", "long-room", 11): "11d95f1dae62a4bbc2b8772055835ff64fafc4def2dd5e24af4040e996f43551",
    ("rover", "small-room", 11): "c15b3634e3929997a91815f9702a1454dbeb1e37348812b15ad3db498c83d5d1",
    ("vacuum", "vacuum-room", 11): "7097d9ad7f14a2003ae962d70c06bd69021fa5a54a8435460848bfd5e2c89a3c",
    ("vacuum", "open-floor", 11): "b8661dfa5085282d2d77c378b7723b121b30e1f18e52fc710241d91dd801fd18",
    # the lab robot's four re-recorded when its encoders' handlers became soft (an ESP32's
    # Pin.irq has no hard argument: ports/esp32/machine_pin.c; docs/lab_robot.md)
    ("lab_robot", "arena", 11): "e010647302e82f46522af2278087b6ede8da97bb78de70f06ac453ad1a5df39e",
    ("lab_robot", "arena-noisy", 11): "a1fe2e33b09c27b2c9056dad67a2601f1bd708642f2d01ba8b4bcf99945aa9d1",
    ("lab_robot_canyon", "canyon", 11): "f8e642fb37b9105521265476ac9cd7f0ca4a46d5eb2c420440b9094c8131b9c9",
    ("lab_robot_canyon", "canyon-noisy", 11): "a7899a49b29eb8438a608b9552d7c9ec39b706ee9718d2fa5b3f8e4e2a90cf72",
    ("pico_bot", "box-ahead", 11): "d57eac9d1f15c3e95747c76de9adb7a9898c24284a6dcbad966ce7a3329469ff",
    ("pico_bot", "open-room", 11): "7544836e57479bb11aa7193beb0251fa38541799460dddbea0ee1a86d54588f5",
    # the pool cleaner as a tracked body over parts: its trace is line for line the one of
    # its plant class (fcd5869d..., aa745c7c...) but for the header's plant (PartsPlant, was
    # PoolCleaner) and its bumpers' signals in the two CFG lines (bumper_front.out, was
    # bumper_front: a part's signals are <name>.<signal>); docs/pool_cleaner.md. Recorded
    # with the absolute folder, then re-recorded with it relative (the same traces).
    ("pool_cleaner", "default", 1): "4577ad759d11cc8e51f2deac1839bde231fce0316c4925ef3c82283f49064524",
    ("pool_cleaner_adc", "default", 1): "12f2dc532fd9e6af36e07bf8ebc3044def2626230cb6285ed1127e92d3628fd0",
    # the duct robot as a differential body over parts: line for line the trace of its plant
    # class (7324cc9c..., 9b8d905e..., f0e0454a..., 4ebdcd72...) but for the header's plant
    # (PartsPlant, was DuctRobot) and its encoders' signals in their CFG lines (enc_l.out, was
    # enc_l); the worlds are the differential body's duct worlds now; docs/duct.md. Recorded
    # with the absolute folder, then re-recorded with it relative (the same traces).
    ("duct", "one-right-branch", 1): "66c62f1749ab403f6e1e2c60512362575c2f446399d96a24688272257dffe7d4",
    ("duct", "multi-branch", 2): "b63877eb9871f2d36a6457ae948edbe4569fecfcf6a05e0ec2c687c513673210",
    ("duct", "straight", 3): "658618a90b2173a52da94b906e2c1c7be8996f6ee1062a3e5dff71bf69fe6c0c",
    ("duct", "bench", 1): "d5a8fd61e903de2fbe7c740495ba333aa1972554515763ba199726eb9ef4c459",
}

RENAMED = {  # app: (its plant class before, {signal now: signal before})
    "rover": ("RoverRoom", {"bumper.out": "bumper"}),
    "vacuum": ("VacuumRobot", {"enc_l.out": "enc_l", "enc_r.out": "enc_r"}),
    "pico_bot": ("TwoWheelRobot", {"start.out": "button.start"}),
    "lab_robot": ("LabRobot", {"jumper.out": "jumper"}),
    "lab_robot_canyon": ("LabRobot", {"jumper.out": "jumper"}),
}


FIRMWARE_BEFORE = {  # the header's firmware identity (a regular expression) as it was when pinned
    "pico_bot": (
        '"files":1,"folder":"examples/pico_bot","sha256":"6c5f9a928e2075ef"',
        '"files":2,"folder":"examples/pico_bot","sha256":"1a975767b221e88a"',
    ),
    "duct": (
        '"files":9,"folder":"firmware/apps/duct","sha256":"[0-9a-f]{16}"',
        '"files":8,"folder":"firmware/apps/duct","sha256":"1bb11c3827138f30"',
    ),
}
"""pico_bot's test_pico_bot.py is not firmware (issue 40: what ``make flash`` puts on a
board, host/rig/targets/boardfs.py); its traces are the same but for that identity in the header.
The duct robot's folder holds the MCU firmware of the robot as built too (robostix.py, which
its one-board firmware never imports: firmware/apps/duct/as_built.toml), counted in the
identity: its one-board traces are the same but for it, whatever robostix.py holds."""


def digest_before(trace: bytes, app: str) -> str:
    """The digest of ``trace`` with the names ``RENAMED`` lists and the firmware identity
    ``FIRMWARE_BEFORE`` gives put back as they were."""
    if app in FIRMWARE_BEFORE:
        now, before = FIRMWARE_BEFORE[app]
        head, _, rest = trace.partition(b"\n")
        trace = re.sub(now.encode(), before.encode(), head, count=1) + b"\n" + rest
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


MCU_SECONDS = {("duct", "bench", 1): 8.0}  # (app, world, seed): its seconds; others: RUN_S
"""How long each run with MCU time on is: a few virtual seconds, so that pinning every app's
worlds adds little to ``make test`` (docs/mcu-time.md, "Default"): RUN_S, the free runs of the
pool cleaners (60 s) and the duct robot (8 s) cut to it, but the duct robot's bench, 8 s as it
was pinned first."""
MCU_CPU = {"pico_bot": "rp2040@125MHz"}
"""The CPU an app's MCU-time digest is pinned on, where its board family has none: pico_bot's
board (``pins``) names no chip; its firmware is a Pico's (GP numbers, the LED on GP25)."""

MCU_DIGESTS = {  # (app, world, seed): the link trace's digest with MCU time on (mcu_cpu: the family's CPU)
    # The rover's and the duct robot's bench were recorded once the collector was modelled on the
    # board's heap and a growth counted the same moved or not (docs/mcu-time.md, "The collector's
    # pause"): the same in a checkout at any path (host/tests/test_mcu_heap.py). A change to the
    # counting interpreter's patch, the cost model or the shim's charging changes them: re-record
    # with the reason. Re-recorded when the scheduler went the port's way (one callback a pending
    # check, at the firmware's branches; a wait serves while the callbacks' compute is within it)
    # and the shim's modules as the sandbox shows them (/_hil/) stopped counting as the firmware's.
    # Every other app's worlds recorded beside them (MCU_SECONDS long), on the same tree.
    ("rover", "room", 11): "999cf71dbcc5d6fa530e9130fd346a294567f9a8c3706ed8f715f1673b34e297",
    ("rover", "long-room", 11): "0cacac25dfe8657b4ea5db1cc0504f01117f97388fe9061c779bf1cce525a733",
    ("rover", "small-room", 11): "87e5612c24a4327691ff6cfdf4b105c668c8d5e2cd924a6dc14dfd1b1ebdabab",
    ("vacuum", "vacuum-room", 11): "8f786b0eba96091eb690f6d682bbe4de2b3a5fdd7e5bbbbb070c43ba22a8e0f7",
    ("vacuum", "open-floor", 11): "fb4e2ef0a4e19b9d17009dc273976291cdea0b523ef801ab74c7e953efe287ca",
    ("lab_robot", "arena", 11): "eb0077d7b313bd34f40b9bb1cf7c4237fe99ece1b21abf7c6e07eded56c73d78",
    ("lab_robot", "arena-noisy", 11): "2e080b958ef0b3ad2d7abe397ca782115fd2c812ef43a781ae81e759fb043d6a",
    ("lab_robot_canyon", "canyon", 11): "29e150cb2702348cbb6e73a34b1284d3fec27034a2bc0fbfd47f1afa5d0d52ad",
    ("lab_robot_canyon", "canyon-noisy", 11): "42bcccf9622a6f196dc8b6a3b27d1a959b9624b992ad4709ebcb99e1033f4c2e",
    ("pico_bot", "box-ahead", 11): "0d5c24ee98c08c89301c175c761feb1b22b2130538abce736a1ab84252358c2c",
    ("pico_bot", "open-room", 11): "e860dfa04e1fcf81ba846dcc89363daf976fed67db8859704a13962f7f6a727c",
    ("pool_cleaner", "default", 1): "15ab3d7830305d0d48cef6bc57b5ad0ae9038d2a9cf95feb27ac378e664584dc",
    ("pool_cleaner_adc", "default", 1): "9983aaf88e8ac590dce1c62841595b8353cbe8ea48927b107f27d09f4043743c",
    ("duct", "one-right-branch", 1): "a12d47cf520aa27844e6d9ba42fb9403fdfaacfd529581f639c31003a9648b91",
    ("duct", "multi-branch", 2): "0898e6e798ddf1f92cd2490a5e38ea0198109a8e9bd8379deb57abf2eef0dd90",
    ("duct", "straight", 3): "4c91ea756d8e46b09af471f2080d8665c8468c482829dd0957f7067812b00341",
    ("duct", "bench", 1): "b4ddece04c7382fd3ca73719e00e92e03e82b888ad4747ebf0527292726d4e33",
}
# (The duct robot's four re-recorded on 1.25, 1.26, 1.27 and 1.28 when the finalisers the interpreter's collector
# runs stopped counting as the firmware's work and the board's collector counted the firmware's
# blocks from its own roots, not the shim's frames and modules: docs/mcu-time.md, "The collector's
# pause". The other apps' did not move.)
# (Every digest of an app on an ESP32 or an RP2040 board re-recorded on 1.25 to 1.28 (2026-11-28)
# when __main__ came to hold what the port's frozen _boot.py leaves there (machine and rp2,
# gc and vfs: docs/shim.md): the firmware's globals, and so its heap, as a board's.
# pico_bot's, on the `pins` board of no family, did not move.)
MCU_DIGESTS_1_26 = {  # MCU_DIGESTS' runs on MicroPython 1.26 (pytest --mpy-version 1.26)
    ("rover", "room", 11): "1dfdae07faf9f5b69a2bbcff57dabdbed53fdc5881057bf0c1dd6d77cf82e446",
    ("rover", "long-room", 11): "d8275821ae9097efd0c528b41b7a81671d9a990f28909380e4afa8db7d939d84",
    ("rover", "small-room", 11): "b3a028a00843195e48729b0cdea0bb11eab5c1ba34ecdc08f1d2816a1908a39c",
    ("vacuum", "vacuum-room", 11): "7ecd508abe93e8993abec8d0f28022843af507e3c548d9b57a8d62ad8466fdd8",
    ("vacuum", "open-floor", 11): "60e34896d4a3914c83cca155e928299a81ae84258e45a309a3df4b0d621b261c",
    ("lab_robot", "arena", 11): "aba2a87c3e2689d81f0c3050f1137b098cdc0376f0754e7f7866ae545fa3ebcc",
    ("lab_robot", "arena-noisy", 11): "246bc2a9c82a81481d7ac72ba157e5a62853319a5653db6450cf6288f4ae1758",
    ("lab_robot_canyon", "canyon", 11): "5f7f9c4160c9a88014c8904cca1791bf3267047bc20e6eed7469a618148ff051",
    ("lab_robot_canyon", "canyon-noisy", 11): "60900306db41b0625f2669ed25c1d91d17d9e69e09ca98677b5a5d605cd116b3",
    ("pico_bot", "box-ahead", 11): "0d5c24ee98c08c89301c175c761feb1b22b2130538abce736a1ab84252358c2c",
    ("pico_bot", "open-room", 11): "e860dfa04e1fcf81ba846dcc89363daf976fed67db8859704a13962f7f6a727c",
    ("pool_cleaner", "default", 1): "4a16d1b34ddbfdfb6f267630d587c00988ee23b7117c9cef586aebf50cf7f3d2",
    ("pool_cleaner_adc", "default", 1): "ecf1116a15120ae45cf2948d5637f88f85c43a3eddae18fba1a3788b36305b02",
    ("duct", "one-right-branch", 1): "5747b8502c498adfe1d18a2fa71f157203e0c3d19cfa31e2db51a089f82ecc49",
    ("duct", "multi-branch", 2): "1eb3b924257d324e95e75471e585d3991b5340301ed427fd46eebe36e7ccf084",
    ("duct", "straight", 3): "461227b7d0bfd4afb210b994ad9496b6f2d57b0468980ab866d8d45c6b652722",
    ("duct", "bench", 1): "d4c74ffe278963d64fb65f1dd048fe36df15f4b2fcb22d4d8ad6cf7a4ac5e85f",
}
# (The duct robot's multi-branch run with MCU time was pinned again when the shim's bus images
# were made cheaper: its trace moved on 1.25 and 1.28, not on 1.26 and 1.27, with no change of its
# own code. The cause: an interpreter's collection, whose moment the shim's allocations set, ran
# finalisers counted as the firmware's calls into C; fixed since, docs/mcu-time.md.)
MCU_DIGESTS_BY_VERSION = {  # the same runs on the other MicroPython versions (pytest --mpy-version)
    # Their link traces without MCU time are the default's (DIGESTS); with it they differ as the
    # firmware's own work differs (docs/shim.md, "On each MicroPython version"): from 1.26
    # asyncio.run executes more bytecodes (its early-exit fix: the rover's first wait ends at
    # 993 us, not 997), and the firmware's modules' bodies execute 5 bytecodes fewer from 1.26
    # and allocate more from 1.28 as each version compiles them (the duct robot's). (pico_bot's
    # are 1.25's on every version.)
    "1.26": MCU_DIGESTS_1_26,
    "1.27": MCU_DIGESTS_1_26,  # (1.26's: its compiler and asyncio count the same)
    "1.28": {  # (1.26's but the duct robot's: its modules allocate more as 1.28 compiles them)
        **MCU_DIGESTS_1_26,
        ("duct", "one-right-branch", 1): "86bed73f308a1698007e4f52706255bf7ff2bf405e43f5fb2215f57c77e5c789",
        ("duct", "multi-branch", 2): "c087df435fa01993ca186eb0497f53bef4ba958a0e7926e99a3dc74a8be4fbf7",
        ("duct", "straight", 3): "509512a16fcfc16135727d3d0c4076a4872b6f2a7c7afe02e8f8641ebcdacea3",
        ("duct", "bench", 1): "593a30060d23a7b5bd0260e51dcc590e529feb7b02298e3e8477120cb35073d7",
    },
}


def _expected(key) -> tuple[dict, str]:
    """The table the default run of ``key`` is held to, and its name (MCU time on by default
    would hold the default runs to MCU_DIGESTS, whose runs are MCU_SECONDS long: not yet)."""
    assert not mcutime.DEFAULT_ON, "MCU time on by default: pin every app's digests with it (see MCU_DIGESTS)"
    return DIGESTS, "DIGESTS"


def app_cpu(app: str) -> str:
    """The CPU of the app's board family (MCU time's default when it is on)."""
    spec = get_app(APP_PATHS.get(app, app))
    return mcutime.family_cpu(spec.board.identity or boards.identity(spec.default_board))


def mcu_cpu(app: str) -> str:
    """The CPU the app's MCU-time digests are pinned on: its family's, else :data:`MCU_CPU`'s."""
    return MCU_CPU.get(app) or app_cpu(app)


@pytest.mark.parametrize("key", list(DIGESTS), ids=lambda k: f"{k[0]}-{k[1]}-s{k[2]}")
def test_link_trace_is_unchanged(make_rig, key):
    table, name = _expected(key)
    if key not in table:
        pytest.fail(f"{key}: no digest in {name} (mcutime.DEFAULT_ON is {mcutime.DEFAULT_ON})")
    _check_digest(make_rig, key, table[key])


FREE_CHECKED = [k for k in DIGESTS if k[1] in ("room", "vacuum-room", "arena", "box-ahead", "bench")]
"""With MCU time off by default, a world of a few apps shows that MPYFIL_CPU=free gives
today's digests; with it on (DEFAULT_ON), every one."""


@pytest.mark.parametrize(
    "key", list(DIGESTS) if mcutime.DEFAULT_ON else FREE_CHECKED, ids=lambda k: f"{k[0]}-{k[1]}-s{k[2]}"
)
def test_cpu_free_gives_todays_digests(make_rig, monkeypatch, key):
    monkeypatch.setenv("MPYFIL_CPU", mcutime.FREE)
    _check_digest(make_rig, key, DIGESTS[key])


def mcu_seconds(key) -> float:
    """How long the run of ``key`` with MCU time on is (:data:`MCU_SECONDS`)."""
    return MCU_SECONDS.get(key, RUN_S)


def _check_digest(make_rig, key, expected: str | None, seconds: float | None = None) -> str:
    """The run's link-trace digest after ``seconds`` (the free run's: SECONDS), held to
    ``expected`` unless None."""
    app, world, seed = key
    name = APP_PATHS.get(app, app)
    seconds = seconds or SECONDS.get(app, RUN_S)
    rig = make_rig(name, seed=seed, plant_options=dict(get_app(name).worlds[world]), trace=True)
    rig.run_for(seconds)
    assert rig.t_us >= seconds * 1e6 and "Traceback" not in rig.console, rig.console[-800:]
    rig.stop()
    trace = (rig.artefacts / "trace.jsonl").read_bytes()
    assert hashlib.sha256(trace).hexdigest() == rig.trace_digest, "the digest is the trace file's"
    trace = as_from_sources(trace, rig)  # (run from a flash: the sources' firmware in its header)
    assert b'"folder":"/' not in trace.split(b"\n", 1)[0], "the header's firmware folder is the repository's"
    got = digest_before(trace, app)
    cpu = os.environ.get("MPYFIL_CPU") or "the default"
    assert expected is None or got == expected, (
        f"{app} in {world}, seed {seed}, cpu {cpu}: expected the link trace's digest {expected}, got {got}"
        f" ({rig.artefacts})"
    )
    return got
