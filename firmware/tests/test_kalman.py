"""The lane filter's gains come from the seed's recursion and equal the C code's tables."""

import pytest
from kalman import DS_M, GAIN_STEPS, LaneFilter, gain_schedule

# seed 000, App. A (sensor.h): kappa1[30], kappa2[30], then KAPP1 / KAPP2
KAPPA1 = [
    0.4,
    0.4239,
    0.434,
    0.4404,
    0.4459,
    0.4512,
    0.4563,
    0.461,
    0.4653,
    0.4691,
    0.4723,
    0.4751,
    0.4775,
    0.4795,
    0.4811,
    0.4824,
    0.4835,
    0.4844,
    0.4852,
    0.4858,
    0.4862,
    0.4866,
    0.4869,
    0.4872,
    0.4874,
    0.4875,
    0.4877,
    0.4878,
    0.4879,
    0.4879,
]
KAPPA2 = [
    0.0,
    0.01,
    0.0303,
    0.0558,
    0.0834,
    0.1111,
    0.1375,
    0.1618,
    0.1836,
    0.2028,
    0.2193,
    0.2333,
    0.2452,
    0.2550,
    0.2632,
    0.2699,
    0.2754,
    0.2799,
    0.2835,
    0.2865,
    0.2889,
    0.2908,
    0.2923,
    0.2936,
    0.2946,
    0.2954,
    0.2961,
    0.2966,
    0.2970,
    0.2973,
]
KAPP1, KAPP2 = 0.4880, 0.2976


def test_gain_schedule_equals_the_codes_kappa_tables_within_1e_4():
    k_d, k_phi = gain_schedule()
    assert len(k_d) == GAIN_STEPS + 1
    for i in range(GAIN_STEPS):
        assert k_d[i] == pytest.approx(KAPPA1[i], abs=1e-4), f"kappa1[{i}]: table {KAPPA1[i]}, got {k_d[i]:.5f}"
        assert k_phi[i] == pytest.approx(KAPPA2[i], abs=1e-4), f"kappa2[{i}]: table {KAPPA2[i]}, got {k_phi[i]:.5f}"
    assert k_d[GAIN_STEPS] == pytest.approx(KAPP1, abs=1e-4) and k_phi[GAIN_STEPS] == pytest.approx(KAPP2, abs=1e-4)


def test_first_gain_is_sigma0_over_r():
    """Sigma_0 = 1 / (1/0.2 + 1/0.3) = 0.12, K_0 = 0.12 / 0.3 = 0.4 exactly (seed 000 §5.4)."""
    k_d, k_phi = gain_schedule()
    assert k_d[0] == pytest.approx(0.4, abs=1e-12) and k_phi[0] == 0.0


def test_the_run_starts_from_the_prior_like_state1():
    """State1 at i == 0: yref + 0.4 (mis - yref); State2: MEANA."""
    f = LaneFilter()
    f.start(5.0, -0.0174, 5.5)
    assert f.d_m == pytest.approx(5.2) and f.phi_rad == pytest.approx(-0.0174) and f.n == 0
    f.start(5.0, 0.01)
    assert f.d_m == 5.0, "no reading: the prior"


def test_predict_turns_first_then_travels_ds():
    f = LaneFilter()
    f.start(5.0, 0.02)
    f.predict(-0.01)
    assert f.phi_rad == pytest.approx(0.01) and f.d_m == pytest.approx(5.0 + DS_M * 0.01) and f.n == 1


def test_a_straight_machine_off_its_lane_is_found_within_a_few_samples():
    """Noise-free readings of a machine 0.3 m past the prior, running parallel."""
    f = LaneFilter()
    f.start(5.0, 0.0, 5.3)
    for _ in range(10):
        f.predict(0.0)
        f.update(5.3)
    assert abs(f.d_m - 5.3) < 0.02 and abs(f.phi_rad) < 0.05, (f.d_m, f.phi_rad)
