"""A rig file says how a campaign's run of it passes (``[report.judge]``): the campaign
takes that judge when it names none, and the judge fails a run on every condition it
misses (in order: a shrink tells the failures apart by them), with its figures; a bad
judge table is refused naming its field."""

from types import SimpleNamespace

import pytest

from host.campaign.judges import declared
from host.campaign.scenario import load_campaign
from host.core.errors import ConfigError
from host.core.paths import REPO
from host.rig.config.app import Judge, Report, RunSettings
from host.rig.config.rigfile import load_rig

TWO_SONAR = str(REPO / "examples" / "two_sonar_bot" / "rig.toml")


def fake_rig(console: str, judge: dict, x_m: float = 1.0, contacts=()):
    truth = {"x_m": x_m, "y_m": 1.0, "contacts": list(contacts), "coverage_fraction": 0.5}
    return SimpleNamespace(
        app=SimpleNamespace(run=RunSettings(report=Report(judge=Judge(**judge)))),
        console=console,
        truth=lambda: truth,
        plant=SimpleNamespace(start_pose=(1.0, 1.0, 0.0)),
        t_us=28_000_000,
    )


def test_a_campaign_of_a_rig_file_with_a_judge_takes_it_and_one_without_takes_the_generic():
    assert load_campaign(TWO_SONAR).judge == "declared"
    assert load_campaign(str(REPO / "examples" / "esp32_car" / "rig.toml")).judge == "generic"
    assert load_campaign(TWO_SONAR, judge="no_contact").judge == "no_contact", "the command line's wins"


@pytest.mark.parametrize(
    ("rig", "passed", "message"),
    [
        (fake_rig("stopped\n", {"console": "stopped", "no_contact": True}), True, ""),
        (fake_rig("driving\n", {"console": "stopped"}), False, "expected 'stopped' on the console"),
        (fake_rig("stopped", {"no_contact": True}, contacts=[(1, 2.0, 1.0)]), False, "expected no contact, got 1"),
        (fake_rig("", {"home_within_m": 0.15}, x_m=1.2), False, "expected home within 0.15 m, got 0.200 m"),
        (fake_rig("", {"min_coverage": 0.95}), False, "expected >= 95% covered, got 50.0%"),
        (
            fake_rig("driving", {"console": "stopped", "no_contact": True}, contacts=[(1, 2.0, 1.0)]),
            False,
            "expected 'stopped' on the console; expected no contact, got 1",
        ),
    ],
)
def test_the_declared_judge_fails_on_every_condition_missed_in_order(rig, passed, message):
    ok, figures, said = declared(rig, True, {"until": None, "seconds": 28})
    assert (ok, said) == (passed, message)
    assert figures["t_end_s"] == 28.0


def test_a_bad_judge_table_is_refused_naming_its_field(tmp_path):
    text = open(TWO_SONAR).read().replace('console = "stopped"', 'console = "stopped"\nmin_coverage = 1.5')
    (tmp_path / "main.py").write_text(open(REPO / "examples" / "two_sonar_bot" / "main.py").read())
    (tmp_path / "rig.toml").write_text(text)
    with pytest.raises(ConfigError, match=r"\[report.judge\] min_coverage: expected 0 to 1, got 1.5"):
        load_rig(tmp_path / "rig.toml")
