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
    # The rover's and the duct robot's bench were recorded once the collector was modelled on the
    # board's heap and a growth counted the same moved or not (docs/mcu-time.md, "The collector's
    # pause"): the same in a checkout at any path (host/tests/test_mcu_heap.py). A change to the
    # counting interpreter's patch, the cost model or the shim's charging changes them: re-record
    # with the reason. Re-recorded when the scheduler went the port's way (one callback a pending
    # check, at the firmware's branches; a wait serves while the callbacks' compute is within it)
    # and the shim's modules as the sandbox shows them (/_hil/) stopped counting as the firmware's.
    # Every other app's worlds recorded beside them (MCU_SECONDS long), on the same tree.
    ("rover", "room", 11): "a3fda950ca280f93726122c74b8a1d1e0e36febff0683dca0917a26d4b3b8b6a",
    ("rover", "long-room", 11): "b5aef6ff5a616e612f902015d809c3d8b1beb2c0aba3fc16002ed6bb96a490ea",
    ("rover", "small-room", 11): "33ac4c8e644ab624884ae39bc68c72adad7060a38dbd7c9b794b4062912f75c5",
    ("vacuum", "vacuum-room", 11): "77e7c8433b86f84562e34afbb35d3e9d815ae2d7b875fa694c46ebcd67d64e73",
    ("vacuum", "open-floor", 11): "a178c7cea1025062ddb23b15cf18d449cdf4796722392c51584b32b49debc649",
    ("lab_robot", "arena", 11): "e9024679952bb879fbf35ec2bd0f69e7d23bb9008183396194c92e00167eea4d",
    ("lab_robot", "arena-noisy", 11): "c32507ca3621f8da03e7b6da3f87b477bc54ea822a22f56718d4a79c3b4bf992",
    ("lab_robot_canyon", "canyon", 11): "62a44ba16574eb0046226a0e0c5e507184603397c135dc9d1ccccfa72f4cbe59",
    ("lab_robot_canyon", "canyon-noisy", 11): "ffe19753c7b758b82de144358cfeda532927d2fc076157fbcf4314d0e9396dac",
    ("pico_bot", "box-ahead", 11): "61135ac70094f0de922196e25eb3682473effae903a71e153d9ac1f4586478a1",
    ("pico_bot", "open-room", 11): "05dec918a1b9ebe006f072756e4e6497fb3ac958db587a730ed76496fbc959b8",
    ("pool_cleaner", "default", 1): "fc556e2aa4ec281a26bec4a576760df8dc6fa46518e0900bff8f222f4841579a",
    ("pool_cleaner_adc", "default", 1): "622ef4667d8b828517af9f2678451e124b458db25247e54b10b97e9e34570e1b",
    ("duct", "one-right-branch", 1): "d0e288685e723d43f8d5690ab71b73eccb3d383987288e0ba7cd6185d9f52a11",
    ("duct", "multi-branch", 2): "90bc305470a609d23ce05d7bbd3aa1811460955abae0b08eac430c82d9c62e8e",
    ("duct", "straight", 3): "ecae9997c49ae93353ea2d08d0d642f7da371ec66c66ba40b223af92a12146cc",
    ("duct", "bench", 1): "1bee210359d9640640bd5d140314369cdda18b602c363a1fd9d9b4c03ebc97e9",
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
    ("rover", "room", 11): "0c61581b7ad08d54b297506ba3583e3edd1e062f896f20331c5941ff8d8d69a6",
    ("rover", "long-room", 11): "05d6bf2835b2aa7d1f658c56c821e67057f000e1c95a8a042a1dfd687d96552e",
    ("rover", "small-room", 11): "3a1bdf3d78c3efbe13093a164f26c7a31b6aa45446debc40a0c62251e9d1b7f3",
    ("vacuum", "vacuum-room", 11): "ed7ef452f251a8f9185931df22625b90bb34cc42cde399c26d1bf5026a02f3a0",
    ("vacuum", "open-floor", 11): "7ede28f009f6ff3bc8afd1499fa208396fae601add9774f86e82fcca82ce145f",
    ("lab_robot", "arena", 11): "57118457d5c3f6075111e923f8dd4a13f1959fceb30c38dc1a81bb2035daaf19",
    ("lab_robot", "arena-noisy", 11): "f7fd38f407d16a6c46660d1f53e375c2d06aa9d88774cfea27f6778d97c402d9",
    ("lab_robot_canyon", "canyon", 11): "49512b30a8d47fb77aa8c70c56d3780e38b36224fa32eea08c95161ca07fdbfb",
    ("lab_robot_canyon", "canyon-noisy", 11): "fc1e9f6e9d6c91d8c35f1e11b3836cce1ee16c5e6a139a48936a2b04cd9d9cdd",
    ("pico_bot", "box-ahead", 11): "61135ac70094f0de922196e25eb3682473effae903a71e153d9ac1f4586478a1",
    ("pico_bot", "open-room", 11): "05dec918a1b9ebe006f072756e4e6497fb3ac958db587a730ed76496fbc959b8",
    ("pool_cleaner", "default", 1): "02643530bf17df0816f104d9e938edf106802e66380ce3d583410b0b34f54ef8",
    ("pool_cleaner_adc", "default", 1): "616fb98598302fc19b893f2a41919150a2547dc7af4ab4c7c70ca6527f54c102",
    ("duct", "one-right-branch", 1): "e0ff683786f1784482ecfb11dd6d916ede19a41c5c4cdd89afea4f30f41ef2ae",
    ("duct", "multi-branch", 2): "1a3455d45533b38c69a0ebab391057ec9118c88fcf5c0c62b2d4f302a968aac4",
    ("duct", "straight", 3): "c20a502991102b2ef728cee81e4d4274ec8a1ac8ded062e5bae1ca46ea47d78b",
    ("duct", "bench", 1): "f44fd090c51d97b9f42e956996c631464c9b02b509f24329679951bfaf2969e0",
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
        ("duct", "one-right-branch", 1): "5bf7fd02a36dbf650c520edbf2f487345179cf8ddf3220730805692988eecac4",
        ("duct", "multi-branch", 2): "b80b45e65c6ebbd1101c1e73b84cbcbb4f348d18032fa1542ea8c029293295ef",
        ("duct", "straight", 3): "b1073131be96a25bc0638d982ee98fa531218bc21bdfcc0e861b011f2866bd39",
        ("duct", "bench", 1): "b7255f2d12768ba687df352543677b3f3882364ab8cba16239035cf3fb48574d",
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
