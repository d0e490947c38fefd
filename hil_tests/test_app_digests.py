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
    # And again when a hard IRQ's handler came to run with the heap locked, as the port's does:
    # Pin.irq takes no **kw (its dict was allocated at each call, in the firmware's count: a
    # pin's irq() is C on a board) and its IRQ object is made once (docs/shim.md, "Hard
    # handlers and the heap"). pico_bot's two did not move.
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
    ("rover", "room", 11): "4ec36b729584d933c8affe9f2cf9ff38cfc5d7ade71c0605da1e03f8df8ff505",
    ("rover", "long-room", 11): "1c6331c7f2ef3b704a2fe8ae989042f5479254dd43896b7fec7a0f676542dfaf",
    ("rover", "small-room", 11): "ab0bb45a7838fc904f8648b7a35aed54ae8f9be2ab7306815dc1a8934f925da9",
    ("vacuum", "vacuum-room", 11): "f314d2b22961ab3fbb1a955bb0392bab0bb65e6b41c092307e75441217681556",
    ("vacuum", "open-floor", 11): "9751ad3ecd5e99aedb5802ca5beca7b1765ce38b0a6f1a90c1be2d939c28874e",
    ("lab_robot", "arena", 11): "dac02d60120b6df26f7af5d205bb59e3e9fb237977f10b6e983a129d396c91aa",
    ("lab_robot", "arena-noisy", 11): "b72ad9af589cc66f53764e53d42148f5ee3e3ab31b6d585c31bbf6d9f49919b3",
    ("lab_robot_canyon", "canyon", 11): "f41c29965ea3db3cccc3a2a5011749e404afa72b69afebfb84a0f43e1154ae6b",
    ("lab_robot_canyon", "canyon-noisy", 11): "2af87dcfec84f79b1415d0e737194a0e744327abf3d893c6afb89385ed2ec828",
    ("pico_bot", "box-ahead", 11): "be436decc81865c089489da30169cf7bf08263200d63370f7c27c7cacd6741f6",
    ("pico_bot", "open-room", 11): "1ef2fdef2cae64e1f0158a48017aa3e819456d04fe6a594db0e76bd17cc43530",
    ("pool_cleaner", "default", 1): "0812ede4ee7a1a511bddc7d5b726fc73e5afbd50fe207e556114f4cd9976cc84",
    ("pool_cleaner_adc", "default", 1): "5b03c35c4d9220dad270bc1da1d489638001b89a8a8a0504eea3bac11cfc6165",
    ("duct", "one-right-branch", 1): "cdba2f2da65a7d973608a6694ce9866fc6d3467e63f0701352de2f528dda4d11",
    ("duct", "multi-branch", 2): "daaf196e66fc311783affd60ecd2929e909b1af470e294b754fd764920d6613f",
    ("duct", "straight", 3): "819640058ef116a568a41c5911c5e807bf432f779a5b227d9b70706e177538b0",
    ("duct", "bench", 1): "e33b39c17cd3bae97cb9bdbaab75fc3346366e447f23581cf172cf3bc34aa41e",
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
    ("rover", "room", 11): "f462b5c6b6754a921f862c4613b4ddcd1e2f6bbf8ba405a439eaabb3541b0b5f",
    ("rover", "long-room", 11): "b3f0362ae28a58eb0b45cc55895b49e45437deae768812291ee5d1e095500ce2",
    ("rover", "small-room", 11): "650bc69cdf1f7a073108194be5053b684aa2e0d2c67d6ea797c2872384db6f10",
    ("vacuum", "vacuum-room", 11): "5d1d66fac2d63650b25ba6ed308c6f9cd352454d98605cb85d13f295aa34dca6",
    ("vacuum", "open-floor", 11): "e36d7d5312907a07e5254ceee8aa3e28ded413ee76d427a95cc0f5cd109a7b66",
    ("lab_robot", "arena", 11): "fee8f381fb129a4cc4c9645334eb06c10a74786ebdc18ed26c6f779a4d7e207d",
    ("lab_robot", "arena-noisy", 11): "3f3d4e278fcebbac3ef9a95cea94f693c2561605bd82dfe68f7dd32c9f8ac3c9",
    ("lab_robot_canyon", "canyon", 11): "b0f00350d6f51be6d9f17b784862429ae50df4c6b39302bfeade0e300a592362",
    ("lab_robot_canyon", "canyon-noisy", 11): "1f7a9566bf8bb5aef4b2de5476e3e78c82ec5bfb0bd43d226e4cfa7ab28b1957",
    ("pico_bot", "box-ahead", 11): "be436decc81865c089489da30169cf7bf08263200d63370f7c27c7cacd6741f6",
    ("pico_bot", "open-room", 11): "1ef2fdef2cae64e1f0158a48017aa3e819456d04fe6a594db0e76bd17cc43530",
    ("pool_cleaner", "default", 1): "24cb6392b67f8c69b0482dfe8524beaa2c5f0147dcb93fad6744e4691181d507",
    ("pool_cleaner_adc", "default", 1): "895f5f71da3875627daa7d66cad129c52fa31047ee72fb53cb8c16180b3a8b0c",
    ("duct", "one-right-branch", 1): "2c642916158a04290faec36d15ac01faf71e98feba91ca5f18d1f5fc0fd399b4",
    ("duct", "multi-branch", 2): "88e8ebf5b7c0d73aea88fa723356a19200ed90f4325f638ad76ad1e95c33f483",
    ("duct", "straight", 3): "87ce8bd06acb4cfa8f29f88b16a64f9393ad3acc137dac8b442e3ffb74f5a7bf",
    ("duct", "bench", 1): "8e7f890bd69901b90cc7422c97ccee2667420bcb7ed81cdcc762385fa423aa4f",
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
        ("duct", "one-right-branch", 1): "6f042249f04535818a82356e3eb3f3e41857168f8af0d859b232feab7bd9f2a3",
        ("duct", "multi-branch", 2): "02817acca21d806b331e7376b3bc7a56d2fe5399a93c1bb5773989cfd1327207",
        ("duct", "straight", 3): "f43258ac42e6fc06a0cf814625a9fc11a8248073816ba70928fc0b95b54f9e3e",
        ("duct", "bench", 1): "5dab11177bfd0b362b5541537ccb22d5235ceb70a499ea989be06b2f53fa693b",
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
