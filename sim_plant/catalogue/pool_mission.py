"""Judge ``pool_mission``: the pool cleaner's mission (seeds 000/001), as a campaign judges
it (hil_tests/campaigns/pool_placement.toml, docs/campaigns.md)."""

import math
import re

from sim_plant.catalogue.base import Judge


class PoolMission(Judge):
    kind = "pool_mission"
    doc = "'done:' within the run and at least 95 % of the pool's floor covered (the pool cleaner)."
    FIGURES = ("coverage",)

    def judge(self, rig, reached: bool, task: dict):
        """The pool cleaner's mission (seeds 000/001, hil_tests/test_pool_cleaner.py): ``done:``
        within the run and at least 95 % of the floor covered. Touching a side wall is a figure,
        not a failure: the first and last lanes run along the walls."""
        truth = rig.truth()
        done = re.search(r"done: pool cleaned in (\d+):(\d+):(\d+)", rig.console)
        mission_s = int(done.group(1)) * 3600 + int(done.group(2)) * 60 + int(done.group(3)) if done else math.nan
        walls = sum(1 for c in truth.get("contacts", ()) if getattr(c, "part", None) == "body")
        figures = {
            "coverage": truth["coverage_fraction"],
            "mission_min": mission_s / 60,
            "reversals": truth.get("reversals", 0),
            "wall_contacts": walls,
        }
        if not done:
            return False, figures, f"expected 'done:' within {task['seconds'] / 60:g} simulated min"
        if truth["coverage_fraction"] < 0.95:
            return False, figures, f"expected >= 95 % of the floor covered, got {truth['coverage_fraction']:.1%}"
        return True, figures, ""
