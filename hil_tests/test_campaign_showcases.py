"""The campaign showcases (docs/campaigns.md), run by ``make campaign``: seed 002's
tether-snag claim over 20 duct runs, and the pool cleaner over 50 placements with sonar
dropouts. Each goes on from the results already in ``build/campaign/<name>/`` (make
campaign's command lines leave them there) and checks the statistics against the seeds."""

import json
import os

import numpy as np
import pytest

from host.campaign import load_campaign
from host.campaign.maps import missed_by_place
from host.campaign.report import wilson, write_report
from host.campaign.runner import run_campaign
from host.core.paths import REPO

pytestmark = [
    pytest.mark.hil,
    pytest.mark.skipif(not os.environ.get("MPY_FIL_SHOWCASES"), reason="make campaign runs the showcases"),
]
SCENARIOS = REPO / "hil_tests" / "campaigns"
WORKERS = int(os.environ.get("CAMPAIGN_WORKERS", "2"))


def campaign_results(name: str):
    campaign = load_campaign(str(SCENARIOS / f"{name}.toml"))
    out = REPO / "build" / "campaign" / name
    results = run_campaign(campaign, out, workers=WORKERS)
    paths = write_report(out, campaign.to_dict(), results)
    return results, paths["html"]


@pytest.mark.timeout(3600)
def test_duct_tether_snag_campaign_agrees_with_the_seeds_18_of_20():
    """Seed 002 §5.7: 18 of 20 runs succeeded, both failures from the tether catching."""
    every, page = campaign_results("duct_snag")
    results = [r for r in every if r["faultset"] == "tether-snags"]
    passed = sum(r["passed"] for r in results)
    lo, hi = wilson(passed, len(results))
    assert len(results) == 20, f"expected 20 runs, got {len(results)}; report: {page}"
    assert lo <= 0.9 <= hi, (
        f"expected the seed's 18/20 within our interval, got {passed}/20 [{lo:.0%}, {hi:.0%}]; {page}"
    )
    unexplained = [r["key"] for r in every if not r["passed"] and not r["figures"].get("snags")]
    assert not unexplained, f"expected every failure to follow a snag, failed without one: {unexplained}; {page}"
    more = [r for r in every if r["faultset"] == "tether-snags-x4"]
    snags = sum(r["figures"].get("snags", 0) for r in more), sum(r["figures"].get("snags", 0) for r in results)
    assert len(more) == 20 and snags[0] > snags[1], f"expected more snags at 0.5 a spin than at 0.29, got {snags}"


@pytest.mark.timeout(4 * 3600)
def test_pool_cleaner_over_50_placements_with_sonar_dropouts_finishes_every_mission():
    """Seeds 000/001 over 50 placements (0-30 cm off the end wall, 5-35 cm off the side wall,
    within 3 degrees) with two 20 s sonar dropouts: every mission ends ("done:") in 50-60
    minutes with at least 88 % of the floor covered. Measured: most runs stay under the
    95 % of the default start (docs/campaigns.md); the report shows by how much."""
    results, page = campaign_results("pool_placement")
    assert len(results) == 50, f"expected 50 runs, got {len(results)}; report: {page}"
    unfinished = [r["key"] for r in results if not 50 <= r["figures"].get("mission_min", 0) <= 60]
    assert not unfinished, f"expected every mission done in 50-60 min, not: {unfinished}; {page}"
    low = [(r["key"], r["figures"]["coverage"]) for r in results if r["figures"]["coverage"] < 0.88]
    assert not low, f"expected at least 88 % covered from every placement, got {low}; {page}"
    summary = json.loads((page.parent / "summary.json").read_text())
    worst = [w["figures"]["coverage"] for w in summary["worst"]]
    lowest = sorted(r["figures"]["coverage"] for r in results)[: len(worst)]
    assert worst == lowest, f"expected the worst runs to be the lowest coverage, got {worst}; {page}"
    for w in summary["worst"]:  # where they missed: the strips along the side walls (docs/campaigns.md)
        with np.load(page.parent / "runs" / w["key"] / "coverage.npz") as grid:
            where = missed_by_place(grid["covered"], grid["free"], grid["extent"])
        sides = sum(area for place, area in where.items() if "side wall" in place)
        assert sides > 0.5 * sum(where.values()), f"{w['key']}: expected most missed along the side walls: {where}"
        assert (page.parent / "maps" / (w["key"].replace("/", "_") + ".png")).is_file(), f"no map of {w['key']}"
