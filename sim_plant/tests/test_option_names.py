"""One name per concept across every catalogue part and body, with its unit in the name
(issue 26, point 3): a table of concept -> the one accepted name and the synonyms it
replaced; every declared option, signal and truth key is scanned for those synonyms and
for a unit its name lacks."""

import pytest

from sim_plant import catalogue
from sim_plant.option_table import Num

ONE_NAME = {
    "wheel size": ("wheel_radius_m", ("wheel_diameter_m", "wheel_diameter", "wheel_radius", "wheel_r_m")),
    "encoder resolution": (
        "lines_per_rev",
        ("slots_per_rev", "encoder_cpr", "counts_per_rev", "cpr", "ppr", "pulses_per_rev", "ticks_per_rev"),
    ),
    "range noise": (
        "noise_sd_m",
        ("sonar_noise_sd_m", "sonar_noise_m", "ranger_noise_sd_m", "noise_m", "range_noise_sd_m", "noise_sd"),
    ),
    "sample period": ("period_us", ("period_ms", "period_s", "sample_period_us", "interval_ms", "interval_us")),
    "nearest range": ("min_range_m", ("min_m", "range_min_m", "sonar_min_m", "min_range")),
    "farthest range": ("max_range_m", ("max_m", "range_max_m", "sonar_max_m", "max_range")),
    "first-order lag": ("time_constant_ms", ("tau_ms", "discharge_tau_ms", "time_constant_s", "tau")),
    "ADC full scale": ("adc_vref_v", ("adc_vref", "vref", "vref_v", "adc_ref_v")),
    "coverage grid cell": ("coverage_cell_m", ("cell_m", "grid_cell_m", "cell_size_m")),
    "switch bounce": ("bounce_us", ("debounce_us", "bounce_ms", "debounce_ms")),
    "top speed": ("v_max_m_s", ("max_speed_m_s", "vmax_m_s", "v_max")),
    "gear ratio": ("gear_ratio", ("gearing", "gear", "ratio_gear")),
}
"""concept -> (the one name, or the ending every name of it has; the synonyms refused)."""

UNIT_SUFFIX = {
    "metres": ("_m",),
    "metres per second": ("_m_s",),
    "microseconds": ("_us",),
    "milliseconds": ("_ms",),
    "seconds": ("_s",),
    "volts": ("_v",),
    "degrees": ("_deg",),
    "radians": ("_rad",),
    "hertz": ("_hz",),
    "revolutions per minute": ("rpm",),
    "volts per metre": ("_v_per_m", "volts_per_m"),
    "volts per second": ("_v_per_s",),
    "degrees per second": ("_deg_per_s",),
}
"""An option's unit (its bounds' ``what``) -> the endings its name may have."""

REFUSED = {synonym: (concept, name) for concept, (name, synonyms) in ONE_NAME.items() for synonym in synonyms}


def declared_names():
    """(where, name) of every option, signal and truth key the catalogue declares."""
    for table in (catalogue.bodies(), catalogue.parts()):
        for kind, cls in table.items():
            for opt in cls.OPTIONS:
                yield f"{kind} option", opt.name
            for sig in getattr(cls, "SIGNALS", ()):
                yield f"{kind} signal", sig.suffix
            for key in getattr(cls, "TRUTH", ()):
                yield f"{kind} truth", key.replace("{name}_", "").replace("{name}.", "")


def synonym_problems(names) -> list[str]:
    problems = []
    for where, name in names:
        if name in REFUSED:
            concept, one = REFUSED[name]
            problems.append(f"{where} {name!r}: the {concept} is called {one!r} everywhere")
    return problems


def test_no_catalogue_option_signal_or_truth_key_names_a_concept_by_a_synonym():
    problems = synonym_problems(declared_names())
    assert not problems, "\n".join(problems)


def test_every_option_with_a_unit_has_the_unit_in_its_name():
    problems = []
    for table in (catalogue.bodies(), catalogue.parts()):
        for kind, cls in table.items():
            for opt in cls.OPTIONS:
                if not isinstance(opt.spec, Num) or opt.spec.what not in UNIT_SUFFIX:
                    continue
                endings = UNIT_SUFFIX[opt.spec.what]
                if not opt.name.endswith(endings):
                    problems.append(
                        f"{kind}.{opt.name}: a number of {opt.spec.what}, its name ends in none of {endings}"
                    )
    assert not problems, "\n".join(problems)


def test_a_concept_the_table_knows_has_its_one_name_where_the_catalogue_uses_it():
    """The accepted names are in use: the table is not a list of words nobody declares."""
    used = {name for _, name in declared_names()}
    for concept, (name, _) in ONE_NAME.items():
        assert name in used, f"{concept}: {name!r} is declared by no part or body"


@pytest.mark.parametrize("synonym", ["min_m", "slots_per_rev", "sonar_noise_m", "period_ms", "cell_m"])
def test_the_scan_fails_for_a_synonym(synonym):
    assert synonym_problems([("a part option", synonym)]), f"expected {synonym!r} refused"
