"""Parts of a robot written as subclasses of the machine classes whose constructors pass the
pin or id to ``super().__init__()`` (``class Battery(ADC): def __init__(self, pin=Pin(26)):
super().__init__(pin)``, made as ``Battery()``): MicroPython makes the instance, runs its
``__init__`` and builds the native base there (py/objtype.c, ``mp_obj_instance_make_new``
and ``native_base_init_wrapper``). The shim's Pin, ADC and UART took the id in ``__new__``
and raised ``TypeError: __new__() takes 2 positional arguments but 1 were given`` (an
object-oriented Pico-Go library's ``Board()``). Each subclass here reads or drives what the
plant has (hil_tests/firmware/picogo_classes, in that library's style, not copied)."""

import re
import shutil
from pathlib import Path

import pytest

pytestmark = pytest.mark.hil
FIRMWARE = Path(__file__).parent / "firmware"


def test_subclasses_of_pin_adc_and_uart_made_without_their_id_work_as_the_board_has_them(make_rig, tmp_path):
    folder = tmp_path / "picogo_classes"
    shutil.copytree(FIRMWARE / "picogo_classes", folder)
    rig = (FIRMWARE / "picogo" / "rig.toml").read_text()
    rig = rig.replace("TRIG = 14\n", "TRIG = 14\nIR = 5\nBT_UART = 0\n")
    parts = '[[plant.parts]]\nkind = "ir_remote"\nname = "remote"\npresses = [[0.3, 0x18, 0.0]]\n\n'
    parts += '[[plant.parts]]\nkind = "uart_wire"\nname = "bt"\n\n'
    rig = rig.replace("[wiring]\n", parts + "[wiring]\n") + 'IR = "remote.out"\nBT_UART = "bt.line"\n'
    (folder / "rig.toml").write_text(rig)
    rig = make_rig(str(folder / "rig.toml"), allow_exit=True)
    rig.expect("done")
    truth = rig.truth()
    where = f"console:\n{rig.console}\ntruth: {truth}"
    assert "types Receiver Battery Radio Led" in rig.console, where
    assert "same pin True led 1" in rig.console, where
    volts = float(re.search(r"^battery ([\d.]+)$", rig.console, re.M).group(1))
    assert abs(volts - truth["battery_v"]) < 2 * 3.3 / 65535 * 2 + 1e-9, f"the plant's {truth['battery_v']} V; {where}"
    assert 'radio b\'{"drive": "forward"}\'' in rig.console, f"the bytes back through the wire; {where}"
    carrier = re.findall(r"^carrier (\d) (\d+)$", rig.console, re.M)
    assert carrier[0][0] == "1" and 300 <= int(carrier[0][1]) < 309, f"in the remote's 9 ms burst; {where}"
    assert carrier[1][0] == "0" and int(carrier[1][1]) > 370, f"after its frame; {where}"
    assert truth["remote_sent"] == [0x18], where
