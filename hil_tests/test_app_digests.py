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
    # All pinned again on 1.25 to 1.28 when a pin's CFG came to be stamped after the compute
    # before it, as an output is (docs/mcu-time.md, "Charging"): every app configures its pins
    # after some compute. The free digests (DIGESTS) did not move.
    # And again when the board's _thread came to be imported only when the firmware imports
    # it (before, at the confinement: a board of 16K could not compile its main.py): the
    # shim's sys.modules holds one module fewer, and the firmware's imports grow it at other
    # points, allocations a board's import makes too (its sys.modules is the firmware's).
    # The rover's and the duct robot's bench were recorded once the collector was modelled on the
    # board's heap and a growth counted the same moved or not (docs/mcu-time.md, "The collector's
    # pause"): the same in a checkout at any path (host/tests/test_mcu_heap.py). A change to the
    # counting interpreter's patch, the cost model or the shim's charging changes them: re-record
    # with the reason. Re-recorded when the scheduler went the port's way (one callback a pending
    # check, at the firmware's branches; a wait serves while the callbacks' compute is within it)
    # and the shim's modules as the sandbox shows them (/_hil/) stopped counting as the firmware's.
    # Every other app's worlds recorded beside them (MCU_SECONDS long), on the same tree.
    ("rover", "room", 11): "6ff5900c28bf0ec833a0a012e42ca62cc33267905d6a533411da2fb2b127399e",
    ("rover", "long-room", 11): "94590087b8dddd90253132853d3f3795a3934c3bbb5158dbfc09993601ce1c68",
    ("rover", "small-room", 11): "9c5db7469808a64a9525db678aa905dd718a0497bf31eb8658264a4624d35846",
    ("vacuum", "vacuum-room", 11): "c8c35931b4acdb50ed988fd55c5e719edc1ae630d21c02ab0a27db04e60e3e23",
    ("vacuum", "open-floor", 11): "b9b4dd2ddf7559b9f80d8b72f92865a3c73eaa1abd253b7f2f1acfc075942af6",
    ("lab_robot", "arena", 11): "3d4d5f09b5b0a3a012981cd53e8045dc4a328e87975e5e1823e853e4c9cc7460",
    ("lab_robot", "arena-noisy", 11): "73c13a413b869aa75623d49fe1684a0cf1ade3aaa316c96ede82e2c14ef2a4cf",
    ("lab_robot_canyon", "canyon", 11): "5acd0948f3eef948558448a81a90bfbc656ab35ce260af994e9030b0d5c7a1ed",
    ("lab_robot_canyon", "canyon-noisy", 11): "ad1a005e6c9d810293a5229618a5b3b6e875fa7fdd89468aca8697abc919afe7",
    ("pico_bot", "box-ahead", 11): "534536be1c0a458b34c1cfff3cd9e521c575a07ed13e0b6a282e4eb79e834ef0",
    ("pico_bot", "open-room", 11): "4fd7bdb28188e24fc8c7fda57f7f91d734cfea911595b92eff0968bb521ce7cb",
    ("pool_cleaner", "default", 1): "cfce4544f51563b55de6bf3d603bf33aff6af16dbdceaef7ad5f8bfe2bf1a428",
    ("pool_cleaner_adc", "default", 1): "4005f044c9e946788b98ee45b56c8c0c55496443b5d50e304cf763a329b0e7a3",
    ("duct", "one-right-branch", 1): "4ec18f46172897ce3a04622bd0caa08807fec58c5e075023bf42e29d8ccfd968",
    ("duct", "multi-branch", 2): "bcf33582de319b4cf7339d90f75867aae11aadd1481cd05f0a25da55c9c71a59",
    ("duct", "straight", 3): "4bf6053ecc7d6bb38b57d4e98de38aa36fd5ee014ba9b4a3983dca7de2e171b5",
    ("duct", "bench", 1): "c672c95584ef5558054ae4db7f2828b6b536d5cfe849af4ac1925cac27436d02",
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
    ("rover", "room", 11): "546764205144da67ee2d58d5c66fc19aae9fc73cff9c43a3d99f0800bdefbd52",
    ("rover", "long-room", 11): "f9e07e250fbbb6e1280197e55d231fc93c7ee60d71b6b67d575edbad5c8b8a65",
    ("rover", "small-room", 11): "53ffdcb22d4f2fbb495521c644f60876b54da6b431348165d1e7824a1c686ccb",
    ("vacuum", "vacuum-room", 11): "1072755484fb71cd4837988a6a82d4ec70caf3bfa2acd5e477be849b71dd494d",
    ("vacuum", "open-floor", 11): "3601467ea0a147f507097538b447f5a1d4772dec0514df385ebfd4c74aff8bc7",
    ("lab_robot", "arena", 11): "3d0d6bec02848c248f69e48ab3f4422ca835db69a41515e006015301e0615edc",
    ("lab_robot", "arena-noisy", 11): "19fc8ba4efdd52b6a99de47d5490c81110aa222e55d663344ec69b907d6fbe7c",
    ("lab_robot_canyon", "canyon", 11): "140e355d5465dfa5ec02f574b0824c8161f02a7922ae1721aed9ab41562cf8ad",
    ("lab_robot_canyon", "canyon-noisy", 11): "b71b71b963f5621dabf813e35e28802f735c070d646459429dac30de56a41620",
    ("pico_bot", "box-ahead", 11): "534536be1c0a458b34c1cfff3cd9e521c575a07ed13e0b6a282e4eb79e834ef0",
    ("pico_bot", "open-room", 11): "4fd7bdb28188e24fc8c7fda57f7f91d734cfea911595b92eff0968bb521ce7cb",
    ("pool_cleaner", "default", 1): "07be660ef53de9d8c1fc6183185eec7605dcabe9e76d6e7162f3cfb8ec0fc5da",
    ("pool_cleaner_adc", "default", 1): "8586ff1b25606111ef1147048f850b49fda58540f4060c6f14e41c9873eb40ab",
    ("duct", "one-right-branch", 1): "43dfc528671ef4a0c7d531dea78ff1369f43e02b4ea11db42305e5d695b49360",
    ("duct", "multi-branch", 2): "8da67565ba9cd3783bbb2a2433c3855cf24bfff15c75c45f0f005b9872189767",
    ("duct", "straight", 3): "1c0c91169f7b4b40093ce36a7d5faf5163e9d6978d948ceac5132ef89aad64e4",
    ("duct", "bench", 1): "4d6358e27d49ce93faf5dca44d8456b186ccb149533d3cd94b4805f9320c8657",
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
        ("duct", "one-right-branch", 1): "9ce27e80cff58c480d3dd64e733631c2f8c99b74c3ebd5c023ad8a5e85d932e2",
        ("duct", "multi-branch", 2): "2c03a637b958d665d53bdf373f9fc9668ae19d33905162afa2e048367bee1d71",
        ("duct", "straight", 3): "0867be75cd3f8565433925976a2242c936f8150e35c4569a59abb9076d051545",
        ("duct", "bench", 1): "8233ea2c0cb21b3db20e9b35b9a2f8260ddbed828f7931d85c393427345dbc72",
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
