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
    # And again when a print() came to leave after the compute before it (MCU time: the clock
    # brought to that instant at the print, so the console's stamp is the board's and each line
    # has its own: _hilsys.before_print, docs/mcu-time.md "Charging"); a few more exchanges.
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
    ("rover", "room", 11): "5ecff1269696e5128cf031d5328ceb7943669540dc33a5c1100d0a24bc1037ec",
    ("rover", "long-room", 11): "5f211445067415246ad5746dfeddf49bf1250f3e41add9b38487d5b1b65a9c72",
    ("rover", "small-room", 11): "d456a046f2fadede6122c7e55bb006f1e240d072957d89ebbd012ceaedf7c80c",
    ("vacuum", "vacuum-room", 11): "14f3cca2394f11c289376f93ed770679c397ca4559eba0bd614627d59f153f00",
    ("vacuum", "open-floor", 11): "4722e39d6b22c372d5992893fd2c7d3f6ed4ce33d0304b7b967ceabc7c42244a",
    ("lab_robot", "arena", 11): "e758ee7dccfa11e81b95456dad9fb32147e35b7df3d005a225efe7ceef8d9c69",
    ("lab_robot", "arena-noisy", 11): "4770f326e8a58cd464fcb4da9639daa12e7989373313303e4197fcd8beb9d0b6",
    ("lab_robot_canyon", "canyon", 11): "9eb715936e7c968f63d0fa713627b4bbed9e4b72c4a0b4c846e011f7c5ad020f",
    ("lab_robot_canyon", "canyon-noisy", 11): "e860464430e864903595500c78bc2d07b0da9552083e9cbcabd8c5b260d95008",
    ("pico_bot", "box-ahead", 11): "041242dc8617cf118144351d0010cb2df96d6916be808e348c2408c1274c7665",
    ("pico_bot", "open-room", 11): "d6a6bb55b95cc597ceae7593390ab29231350f5fcda2f3168807296224c47f69",
    ("pool_cleaner", "default", 1): "0812ede4ee7a1a511bddc7d5b726fc73e5afbd50fe207e556114f4cd9976cc84",
    ("pool_cleaner_adc", "default", 1): "5b03c35c4d9220dad270bc1da1d489638001b89a8a8a0504eea3bac11cfc6165",
    ("duct", "one-right-branch", 1): "8d88f95c2fd4404e7f15dc052328c17ceb11b17410bf9dfe6b684016c7f219bf",
    ("duct", "multi-branch", 2): "3de60297258bc79030b5f52e3dd19c85660c9ca2ad315b61d64e435cfec7dc3d",
    ("duct", "straight", 3): "2d10c1157f32c5c4cc443fa6da26a233d86fafd3469c3625bbfef6c08b673434",
    ("duct", "bench", 1): "8fb5a26c40a7dd4de46ae0985113e6691214030d9ba0c82d52e72b4a3fa57270",
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
    ("rover", "room", 11): "9324f0b431a9a9550074f070dfd9e68ccb13cc811684281d3414924587f7b49f",
    ("rover", "long-room", 11): "33bdaa7f403417009299f9f728493d970f979d6be72f64b01505411797f6a959",
    ("rover", "small-room", 11): "d9c50b7cc5689665b272a66e6e186479b250195ef5092ce590387e2cb3ef5894",
    ("vacuum", "vacuum-room", 11): "3facfd62bcd8709abb62a3a2b3ca2b4379fc1540b275a517ffa9558e80709844",
    ("vacuum", "open-floor", 11): "3661ba9c33b1a033ddef1e478b3891a7db4857b145097ab1c87a5591d05ac9ba",
    ("lab_robot", "arena", 11): "e56e0a6967d6bc8699deb815d8e428d36bad9e08914fb9c8b8631e2bb8905ac7",
    ("lab_robot", "arena-noisy", 11): "ea96c2d979cb6bfa2f190ae3786d2ba285b556e3ee04858c9564553d86c69f08",
    ("lab_robot_canyon", "canyon", 11): "bacc15453c2fef5c2962241ee80c1cc5dce8993db8bad8f496643fe17bde1af6",
    ("lab_robot_canyon", "canyon-noisy", 11): "e9e221cb6a1db4e0f08dbe5a6175cb44e03a050e1a054189807beabdba715f2d",
    ("pico_bot", "box-ahead", 11): "041242dc8617cf118144351d0010cb2df96d6916be808e348c2408c1274c7665",
    ("pico_bot", "open-room", 11): "d6a6bb55b95cc597ceae7593390ab29231350f5fcda2f3168807296224c47f69",
    ("pool_cleaner", "default", 1): "24cb6392b67f8c69b0482dfe8524beaa2c5f0147dcb93fad6744e4691181d507",
    ("pool_cleaner_adc", "default", 1): "895f5f71da3875627daa7d66cad129c52fa31047ee72fb53cb8c16180b3a8b0c",
    ("duct", "one-right-branch", 1): "78554afb58c98a7d46b26e5bbb96f964c21e4c41c24acc12a4b508d645804fce",
    ("duct", "multi-branch", 2): "17249ca626b185bedac788f65b6323bbb68ed67bd85a59751f2b2b28b647e215",
    ("duct", "straight", 3): "fe84c3436e62394dcaf6a6c0ab076c86a75ea4e793d7d8d8c12778accf00b340",
    ("duct", "bench", 1): "217bafa87ad942976e3e2934d5d7510b43510c7991b8c2ed545aab5d257cb6d8",
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
        ("duct", "one-right-branch", 1): "c077a08dee3f234fb4d71aa89065bb703a9f66c1a0d9a4ee7c5d2f2fef0aaeae",
        ("duct", "multi-branch", 2): "b1dde31a866faed7891a79a09d8b17bdd35ed43cf7eee310b2342fe4cb50fe76",
        ("duct", "straight", 3): "98bbba5197e0d4461f7aeec117a83ff02903f1ce334ddfbbc135e2f813a3f67d",
        ("duct", "bench", 1): "c67020ca63eab03477cd5264477316ac66fd595cf437546189b730514708d0b6",
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
