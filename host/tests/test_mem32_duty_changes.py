"""A PWM slice run through mem32 alone (host/tests/firmware/mem32_cc_later): its pins given
to the PWM function by FUNCSEL, then each CC write a new duty, as on an RP2040 (datasheet
4.5.2.6: CC is double-buffered and takes effect at the counter's wrap, each period).

The PWM object the shim makes behind the first register write that drives a pin
(``PWM._from_registers``) must leave FUNCSEL as the firmware set it: were its pin made
``Pin(gpio, Pin.OUT)``, its init would put FUNCSEL back to SIO (``_hilreg.pin_state``), the
first duty would reach the plant and every later CC write would be skipped
(``_pwm_apply`` drives only pins whose FUNCSEL is PWM)."""

import pytest

from host.tests.conftest import FIRMWARE, bench_app, results
from host.tests.test_mem32_registers import PINS, ROBOT, RP2040, WIRING

pytestmark = pytest.mark.hil


def test_each_cc_write_after_funcsel_changes_the_duty_the_plant_sees(make_rig):
    app = bench_app("mem32_cc_later", ROBOT, board="pins", identity=RP2040, wiring=WIRING, pins=PINS)
    rig = make_rig(app, main_dir=FIRMWARE / "mem32_cc_later", allow_exit=True)
    speeds = []
    for t_s in (0.05, 0.15, 0.25):  # half, full, stopped
        rig.run_for(t_s - rig.truth()["t_us"] / 1e6)
        speeds.append([abs(w) for w in rig.truth()["wheel_rad_s"]])
    rig.stop()
    r = results(rig.console)
    half, full, stopped = speeds
    assert half[0] > 0 and half[0] == pytest.approx(half[1]), (speeds, rig.console)
    assert r["funcsel"] == [4, 4], f"FUNCSEL of GP14, GP15 after the run (4: PWM): {r.get('funcsel')}"
    assert full[0] > 1.5 * half[0], f"CC 6000 of 6000 after CC 3000: wheel speeds {speeds}"
    assert stopped == [0.0, 0.0], f"CC 0: wheel speeds {speeds}"
