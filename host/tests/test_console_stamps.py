"""console.log stamps each line with the virtual instant it was printed at, the last lines
before the firmware ends included: they carry the instant of its end (its EXIT, or the
FAULT of what it raised), not the end of the run (docs/reliability.md)."""

import pytest

from host.artefacts.console import stamped_lines
from host.core.errors import FirmwareError
from host.tests.test_endings import BENCH

pytestmark = pytest.mark.hil

ENDINGS = {
    "returns": "",
    "exits": "import sys\nsys.exit(0)\n",
    "raises": "raise ValueError('the end')\n",
}


@pytest.mark.parametrize("ending", ENDINGS)
def test_the_last_lines_before_the_firmware_ends_carry_the_instant_they_were_printed_at(make_rig, tmp_path, ending):
    folder = tmp_path / "bot"
    folder.mkdir()
    main = "import time\nprint('boot')\ntime.sleep_ms(300)\nprint('last words')\nprint('and more')\n"
    (folder / "main.py").write_text(main + ENDINGS[ending])
    (folder / "rig.toml").write_text('[board]\nfamily = "esp32"\n[board.pins]\nLED = 2\n' + BENCH)
    rig = make_rig(str(folder / "rig.toml"), allow_exit=True)
    if ending == "raises":
        with pytest.raises(FirmwareError):
            rig.run_for(1.0)
    else:
        rig.run_for(1.0)
    rig.stop()
    lines = list(stamped_lines(rig.artefacts / "console.log"))
    assert lines[:3] == [(0, "boot"), (300_000, "last words"), (300_000, "and more")], lines
    assert all(t == 300_000 for t, _ in lines[1:]), f"a line stamped after the firmware ended at 0.3 s: {lines}"
