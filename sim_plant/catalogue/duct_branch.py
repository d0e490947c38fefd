"""Judge ``duct_branch``: the duct robot's single right branch run (seed 002, §5.7), as a
campaign judges it (hil_tests/campaigns/duct_snag.toml, docs/campaigns.md)."""

import math

from sim_plant.catalogue.base import Judge


class DuctBranch(Judge):
    kind = "duct_branch"
    doc = "One branch and two ends explored, the list empty, and home within 150 mm (the duct robot)."
    FIGURES = ("home_off_m",)

    def judge(self, rig, reached: bool, task: dict):
        """Seed 002's single right branch run (§5.7): one branch and two ends explored, the
        list empty, and the robot really within 150 mm of its start (hil_tests/test_duct.py)."""
        truth = rig.truth()
        start = rig.plant.start_pose
        off = math.hypot(truth["x_m"] - start[0], truth["y_m"] - start[1])
        explored = "explored: 1 branches found, 2 ends, 0 left" in rig.console
        figures = {
            "home_off_m": off,
            "t_end_s": rig.t_us / 1e6,
            "snags": truth.get("fault_snags", truth.get("snags", 0)),
        }
        if not reached:
            return False, figures, f"expected the exploration to end within {task['seconds']:g} s"
        if not explored:
            line = next((ln for ln in rig.console.splitlines() if "explored:" in ln), "")
            return False, figures, f"expected one branch and two ends explored, got {line.strip()!r}"
        if off > 0.15:
            return False, figures, f"expected home within 150 mm, got {off * 1000:.0f} mm off"
        return True, figures, ""
