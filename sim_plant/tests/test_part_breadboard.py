"""The breadboard parts a Wokwi diagram has (docs/parts.md, docs/wokwi.md): a knob's and a
light sensor's ADC readings, a slide switch's level, a relay's contact, an RGB LED's
colour, and the desk, a still body a ranger sees a box from."""

import pytest

from sim_plant.catalogue.assembly import assemble
from sim_plant.catalogue.base import PartsError


def bench(*parts):
    return assemble({"body": "bench", "parts": list(parts)})


@pytest.mark.parametrize(
    "lux, volts",  # Wokwi's table for its photoresistor module at VCC = 5 V (gamma 0.7, rl10 50)
    [(0.1, 4.96), (1, 4.81), (10, 4.17), (50, 3.09), (100, 2.50), (400, 1.37), (1000, 0.83), (10_000, 0.19)],
)
def test_the_photoresistor_reads_wokwis_table(lux, volts):
    plant = bench({"kind": "photoresistor", "name": "ldr", "lux": lux, "supply_v": 5.0, "adc_vref_v": 5.0})
    assert abs(plant.output("ldr.ao") / 65535 * 5.0 - volts) < 0.01
    assert plant.output("ldr.do") == int(volts > 2.5), "high when dark (above 2.5 V)"


def test_a_photoresistor_on_the_supply_side_reads_higher_in_brighter_light():
    dim, bright = (
        bench(
            {"kind": "photoresistor", "name": "ldr", "lux": lux, "ldr_at": "supply", "supply_v": 5.0, "adc_vref_v": 5.0}
        )
        for lux in (10, 1000)
    )
    # (the 10 kOhm's share: Wokwi's table's complement, 5 - 4.17 V and 5 - 0.83 V)
    assert (
        abs(dim.output("ldr.ao") / 65535 * 5.0 - 0.83) < 0.01
        and abs(bright.output("ldr.ao") / 65535 * 5.0 - 4.17) < 0.01
    )
    assert (dim.output("ldr.do"), bright.output("ldr.do")) == (1, 0), "still high when dark"


def test_a_knob_reads_its_share_of_the_supply_clipped_at_the_adc_full_scale():
    plant = bench(
        {"kind": "potentiometer", "name": "a", "position": 0.25},
        {"kind": "potentiometer", "name": "b", "position": 1.0, "supply_v": 5.0},
    )
    assert plant.output("a.sig") == round(0.25 * 65535) and plant.output("b.sig") == 65535


def test_a_slide_switch_reads_the_side_its_handle_is_on():
    plant = bench(
        {"kind": "slide_switch", "name": "l"},
        {"kind": "slide_switch", "name": "r", "position": "right", "right_level": 0},
    )
    assert (plant.output("l.out"), plant.output("r.out")) == (0, 0)
    with pytest.raises(PartsError, match="position"):
        bench({"kind": "slide_switch", "name": "x", "position": "middle"})


def test_a_relay_closes_at_its_active_level():
    plant = bench({"kind": "relay", "name": "npn"}, {"kind": "relay", "name": "pnp", "active_low": True})
    for level in (1, 0, 1):
        plant.set_input("npn.in", level)
        plant.set_input("pnp.in", level)
    truth = plant.truth()
    assert (truth["npn_closed"], truth["pnp_closed"], truth["npn_switches"], truth["pnp_switches"]) == (1, 0, 3, 2)


def test_an_rgb_led_shows_levels_or_duties_common_anode_or_cathode():
    plant = bench(
        {"kind": "rgb_led", "name": "k", "common": "cathode"},
        {"kind": "rgb_led", "name": "a", "common": "anode", "signal": "duty"},
    )
    plant.set_input("k.r", 1)
    plant.set_input("k.b", 1)
    plant.set_input("a.r", 65535)
    plant.set_input("a.g", 0)
    plant.set_input("a.b", 65535)
    truth = plant.truth()
    assert truth["k_rgb"] == 0xFF00FF and truth["a_rgb"] == 0x00FF00 and truth["a_g"] == 1.0


def test_a_ranger_on_the_desk_sees_the_box_in_front_of_it():
    plant = assemble(
        {
            "body": "desk",
            "room_w_m": 6.0,
            "room_h_m": 2.0,
            "start_pose": [1.0, 1.0, 0.0],
            "obstacles": [[1.0 + 0.8 + 0.05, 1.0, 0.1, 1.2]],
            "parts": [{"kind": "hcsr04", "name": "s", "noise_sd_m": 0.0}],
        }
    )
    plant.set_input("s.trig", 1)
    plant.advance_to(20)
    plant.set_input("s.trig", 0)
    changes = plant.advance_to(40_000)
    rise, fall = [c.t_us for c in changes if c.name == "s.echo"][:2]
    assert abs((fall - rise) / 58.31 - 80) < 0.1, "the echo of a box 80 cm away"
    assert plant.pose_at(30_000) == (1.0, 1.0, 0.0), "the desk never moves"
