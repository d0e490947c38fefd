"""The catalogue entries our tracked pool cleaner and the duct robot brought: the
``tracked`` body and its ``track`` parts, the ``echo_sounder``, the ``amplitude_sonar``
array, and a part's option set from outside as ``"<part>.<option>"``."""

import pytest

from sim_plant.catalogue.assembly import assemble
from sim_plant.catalogue.base import PartsError
from sim_plant.physics.amplitude_sonar import AmplitudeSonarArray
from sim_plant.tests.rigs import duct_robot, pool_cleaner

TRACKS = [{"kind": "track", "name": "track_l", "side": "left"}, {"kind": "track", "name": "track_r", "side": "right"}]


def test_a_tracked_body_needs_both_tracks():
    with pytest.raises(PartsError, match="needs a track that stops right"):
        assemble({"body": "tracked", "parts": TRACKS[:1]})


def test_the_amplitude_sonars_are_one_array_and_must_agree_on_what_they_share():
    plant = duct_robot()
    (array,) = [p for p in plant.parts if isinstance(p, AmplitudeSonarArray)]
    assert [ch.name for ch in array.channels] == ["sonar_f.adc", "sonar_l.adc", "sonar_r.adc"]
    assert [ch.gain for ch in array.channels] == [1.0, 1.05, 0.95]
    with pytest.raises(PartsError, match=r"\(sonar_l\) noise_sd_v: the amplitude sonars share it"):
        duct_robot(**{"sonar_l.noise_sd_v": 0.0})


def test_a_part_option_from_outside_names_a_part_of_the_rig():
    assert pool_cleaner(**{"sonar.period_us": 250_000}).sample_period_us("sonar.uart") == 250_000
    with pytest.raises(PartsError, match=r"\[plant\] sonar_x.period_us: expected <part name>.<option>"):
        pool_cleaner(**{"sonar_x.period_us": 250_000})
    with pytest.raises(PartsError, match=r"\(sonar\) period_us: expected"):
        pool_cleaner(**{"sonar.period_us": -1})


def test_an_analog_echo_sounder_has_one_transducer():
    with pytest.raises(PartsError, match="transducers: an ADC output has one transducer"):
        pool_cleaner(**{"sonar.output": "adc"})


def test_without_its_own_bumper_logic_the_machine_stays_pressed_on_the_end_wall():
    plant = pool_cleaner("rig-adc.toml", start_pose=(23.0, 4.0, 0.0), reverse_at_bumpers=False)
    plant.advance_to(12_000_000)
    truth = plant.truth()
    assert truth["reversals"] == 0 and truth["direction"] == 1
    assert plant.output("bumper_front.out") == 0, "pressed against the wall it keeps pushing"
