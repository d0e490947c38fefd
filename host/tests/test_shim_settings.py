"""The shim's settings come in WELCOME (docs/protocol.md, "Settings"): what a rig file sets
(the console's rate, the ticks' wrap, the flash's size) reaches the firmware through it, the
interpreter's environment no longer carries it, and a board in the loop is told no console
time (its own UART's is real)."""

import textwrap
from pathlib import Path

import pytest

from host.device.pil import BoardTarget
from host.rig.config.rigfile import load_rig
from host.rig.targets.firmware import CONSOLE_BAUD, TICKS_WRAP_S, Firmware, ShimSettings
from host.shim import _hilframe as F
from host.tests.conftest import results

ENVIRONMENT = {"PATH", "MICROPYPATH", "HIL_LINK", "HIL_COVERAGE_FD", "HIL_PURE"}
"""What stays in the interpreter's environment: what must be there before the link opens."""

RIG = """
name = "settings"
[board]
console_baud = 9600
flash_size = "1M"
[board.pins]
LED = 2
[interpreter]
ticks_wrap_s = 2.5
[plant]
body = "bench"
[wiring]
LED = "probe:led"
"""

MAIN = """
import os
import time

print("R wrap_ms", time.ticks_diff(0, time.ticks_ms()))
s = os.statvfs("/")
print("R flash", s[0] * s[2])
line = "x" * 999
t0 = time.ticks_us()
print(line)
print("R print_us", time.ticks_diff(time.ticks_us(), t0))
"""


@pytest.fixture
def rig_file(tmp_path) -> Path:
    folder = tmp_path / "settings"
    folder.mkdir()
    (folder / "main.py").write_text(textwrap.dedent(MAIN))
    (folder / "rig.toml").write_text(textwrap.dedent(RIG))
    return folder / "rig.toml"


def environ(pid: int) -> dict[str, str]:
    raw = Path(f"/proc/{pid}/environ").read_bytes()
    return dict(item.split("=", 1) for item in raw.decode(errors="replace").split("\0") if "=" in item)


@pytest.mark.hil
def test_a_rig_files_settings_reach_the_shim_in_welcome_and_not_in_its_environment(make_rig, rig_file):
    rig = make_rig(str(rig_file), allow_exit=True)
    env = environ(rig.target.proc.pid)  # (the process the interpreter runs in, after the handshake)
    rig.run_for(2.0)
    rig.stop()
    got = results(rig.console)
    hil = {name for name in env if name.startswith("HIL_")}
    assert hil <= ENVIRONMENT, f"expected only {sorted(ENVIRONMENT)} in the environment, got {sorted(hil)}"
    assert 2400 < got["wrap_ms"] <= 2500, f"expected the ticks to wrap 2.5 s in (ticks_wrap_s), got {got}"
    assert got["flash"] == 1 << 20, f"expected the 1M flash_size as the filesystem's bytes, got {got}"
    # 1000 bytes at 9600 baud, 10 bits each, behind the two lines printed before (31 bytes
    # still in the UART): print() returns once the rest fits the UART's 128-byte FIFO
    want_us = (31 + 1000 - 128) * 10 * 1_000_000 // 9600
    assert abs(got["print_us"] - want_us) <= 2, f"expected {want_us} µs for the print at 9600 baud, got {got}"


def test_the_environment_holds_only_what_must_be_there_before_the_link_opens(rig_file, monkeypatch):
    monkeypatch.delenv("HIL_PURE", raising=False)
    firmware = Firmware.from_app(load_rig(rig_file), None)
    firmware.board_root = rig_file.parent
    env = firmware.env("/dev/pts/0")
    assert set(env) == {"PATH", "MICROPYPATH", "HIL_LINK"}, sorted(env)
    settings = firmware.shim_settings()
    assert (settings.console_baud, settings.ticks_wrap_s, settings.flash_bytes) == (9600, 2.5, 1 << 20), settings
    assert settings.board_fs == str(rig_file.parent), settings


def test_each_setting_has_its_one_default_on_the_host_and_the_codec_carries_them_all():
    packed = ShimSettings().packed()
    assert set(packed) == set(F.WELCOME_NUMBERS) | set(F.WELCOME_TEXTS), sorted(packed)
    assert packed["console_baud"] == CONSOLE_BAUD and packed["ticks_wrap_ms"] == TICKS_WRAP_S * 1000, packed
    proto, mode, t_us, flags, back = F.unpack_welcome(F.pack_welcome(F.MODE_LOCKSTEP, 7, 0, packed))
    assert (proto, mode, t_us, flags, back) == (F.PROTO_VERSION, F.MODE_LOCKSTEP, 7, 0, packed), back


def test_a_board_in_the_loop_is_told_no_console_time_and_nothing_of_the_hosts(rig_file):
    """Its own UART's time is real (a modelled one would come on top); its heap, CPU and
    flash are its own; the entry and the ticks' wrap are the rig file's."""
    firmware = Firmware.from_app(load_rig(rig_file), None)
    firmware.board_root = rig_file.parent
    firmware.cpu = "rp2040@125MHz"
    settings = BoardTarget("/dev/null").shim_settings(firmware)
    assert settings == ShimSettings(entry="main.py", console_baud=0, ticks_wrap_s=2.5), settings
    assert firmware.shim_settings().cpu == "rp2040@125MHz", "expected the unix port to be told the CPU"
