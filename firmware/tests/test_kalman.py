"""The lane filter's gains come from the seed's recursion and equal the C code's tables."""

import pytest
from kalman import DS_M, GAIN_STEPS, LaneFilter, gain_schedule

# seed 000, App. A (sensor.h): kappa1[30], kappa2[30], then KAPP1 / KAPP2
KAPPA1 = [.4, .4239, .434, .4404, .4459, .4512, .4563, .461, .4653, .4691, .4723, .4751, .4775, .4795, .4811,
          .4824, .4835, .4844, .4852, .4858, .4862, .4866, .4869, .4872, .4874, .4875, .4877, .4878, .4879, .4879]
KAPPA2 = [.0, .01, .0303, .0558, .0834, .1111, .1375, .1618, .1836, .2028, .2193, .2333, .2452, .2550, .2632,
          .2699, .2754, .2799, .2835, .2865, .2889, .2908, .2923, .2936, .2946, .2954, .2961, .2966, .2970, .2973]
KAPP1, KAPP2 = .4880, .2976


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
