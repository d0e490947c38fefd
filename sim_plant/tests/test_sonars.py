"""The analog ultrasonic ranger read through an ADC (the design card's "ADC sonar")."""

import math
import statistics

import numpy as np
import pytest

from sim_plant.sonars import MAXBOTIX_V_PER_M, Adc, BeamRangeModel
from sim_plant.world import rectangle

WORLD = rectangle(10.0, 10.0)


def test_adc_reports_counts_as_read_u16_does():
    """MicroPython's ADC.read_u16 scales an n-bit reading to 0..65535."""
    assert Adc(12, 3.3).u16(3.3) == 65535 and Adc(12, 3.3).u16(0.0) == 0
    assert Adc(12, 3.3).u16(1.65) == (2048 << 4) | (2048 >> 8)
    assert Adc(10, 5.0).u16(5.0 * 512 / 1023) == (512 << 6) | (512 >> 4)
    assert Adc(8, 5.0).u16(2.5) == 128 * 257
    assert Adc(12, 3.3).u16(9.9) == 65535, "clipped at full scale"


def test_maxbotix_law_is_vcc_over_512_per_inch():
    assert MAXBOTIX_V_PER_M * 0.0254 == pytest.approx(3.3 / 512)


def test_noise_and_clamping():
    model = BeamRangeModel(noise_sd_m=0.02, min_m=0.2, max_m=4.0)
    rng = np.random.default_rng(1)
    readings = [model.measure(0, (5.0, 5.0, 0.0), WORLD, rng)[1] for _ in range(2000)]
    assert set(readings) == {4.0}, "a wall beyond max_m reads max_m"
    near = [model.measure(0, (9.9, 5.0, 0.0), WORLD, rng)[1] for _ in range(50)]
    assert min(near) == 0.2, "nothing reads nearer than min_m"
    mid = [model.measure(0, (7.0, 5.0, 0.0), WORLD, rng) for _ in range(2000)]
    assert mid[0][0] == pytest.approx(3.0)
    assert statistics.mean(r for _, r in mid) == pytest.approx(3.0, abs=0.003)
    assert statistics.stdev(r for _, r in mid) == pytest.approx(0.02, rel=0.1)


def test_beam_incidence_and_dropouts():
    rng = np.random.default_rng(2)
    beam = BeamRangeModel(noise_sd_m=0.0, beam_half_angle_deg=10.0)
    tilted = (7.0, 5.0, math.radians(20.0))
    assert beam.measure(0, tilted, WORLD, rng)[1] == pytest.approx(3.0 / math.cos(math.radians(10.0)))
    steep = BeamRangeModel(noise_sd_m=0.0, max_incidence_deg=15.0, no_echo="none")
    assert steep.measure(0, tilted, WORLD, rng)[1] is None
    lossy = BeamRangeModel(noise_sd_m=0.0, dropout_p=0.3)
    got = [lossy.measure(0, (7.0, 5.0, 0.0), WORLD, rng)[1] for _ in range(2000)]
    assert sum(r == 4.0 for r in got) / len(got) == pytest.approx(0.3, abs=0.03), "a missed echo reads max_m"
