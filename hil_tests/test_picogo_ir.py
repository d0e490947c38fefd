"""An NEC remote through an IR receiver (the ``ir_remote`` part) decoded in Python, as
the Pico-Go's published demos decode it (polling the pin, counting 100 us sleeps) and as
IRQ-driven decoders do (``ticks_us()`` at each falling edge), with the CPU's time free and
with an RP2040's (docs/mcu-time.md): each key the plant sent is decoded, in order, within
a few ms of its frame's end (hil_tests/firmware/picogo_ir, written in those styles, not
copied). With nothing on the receiver's pin the polling decoder read no key."""

import re
import shutil
from pathlib import Path

import pytest

pytestmark = pytest.mark.hil
FIRMWARE = Path(__file__).parent / "firmware"
KEYS = "presses = [[0.3, 0x18, 0.0], [0.6, 0x5a, 0.25], [1.0, 0x1c, 0.0], [1.5, 0x45, 0.0], [1.8, 0x07, 0.0]]"


LAST_SPACE_US = 9_000 + 4_500 + 32 * 1_125 + 16 * 1_125
"""A frame's last space ends (its last burst begins) this long after its start: address 0 and
each byte's inverse make 16 ones (2.25 ms a bit) and 16 zeros (1.125 ms)."""


@pytest.mark.parametrize("cpu", ["free", "rp2040@125MHz"])
def test_picogo_remote_keys_decoded_by_polling_and_by_pin_irq(make_rig, monkeypatch, tmp_path, cpu):
    monkeypatch.setenv("MPYFIL_CPU", cpu)
    folder = tmp_path / "picogo_ir"
    shutil.copytree(FIRMWARE / "picogo_ir", folder)
    rig = (FIRMWARE / "picogo" / "rig.toml").read_text()
    rig = rig.replace("TRIG = 14\n", "TRIG = 14\nIR = 5                     # the IR receiver's output\n")
    rig = rig.replace("[wiring]\n", f'[[plant.parts]]\nkind = "ir_remote"\nname = "remote"\n{KEYS}\n\n[wiring]\n')
    (folder / "rig.toml").write_text(rig + 'IR = "remote.out"\n')
    rig = make_rig(str(folder / "rig.toml"), allow_exit=True)
    rig.expect("done")
    truth = rig.truth()
    where = f"console:\n{rig.console}\ntruth: {truth}\nartefacts: {rig.artefacts}"
    assert truth["remote_sent"] == [0x18, 0x5A, 0x1C, 0x45, 0x07], where
    polled = [(int(k, 16), int(t)) for k, t in re.findall(r"^poll 0x([0-9a-f]+) (\d+)$", rig.console, re.M)]
    irq = [
        (int(k, 16), int(n), int(t)) for k, n, t in re.findall(r"^irq 0x([0-9a-f]+) (\d+) (\d+)$", rig.console, re.M)
    ]
    assert [k for k, _ in polled] == [0x18, 0x5A, 0x1C], f"the polling decoder's keys; {where}"
    assert [k for k, _n, _ in irq] == [0x45, 0x07] and all(n == 34 for _k, n, _ in irq), f"the IRQ's; {where}"
    for (key, t_us), pressed_s in zip(polled, (0.3, 0.6, 1.0), strict=True):
        end = pressed_s * 1e6 + LAST_SPACE_US
        assert end <= t_us <= end + 1_000, (
            f"key {key:#x} decoded at {t_us} us, expected within 1 ms after its last space ends at {end:.0f} us "
            f"(the decoder sees the last burst begin at its next 100 us poll); {where}"
        )
