"""How a campaign's run is judged: each judge reads the finished rig (console, ground
truth, budgets) and gives (passed, figures, message). The figures are numbers, the
scenario's own (coverage, mission time, distance from home); the message says why a run
failed. ``docs/campaigns.md`` lists them."""

import math
import re


def generic(rig, reached: bool, task: dict):
    """Passes when the run reached its ``until`` text (if it has one)."""
    figures = {"t_end_s": rig.t_us / 1e6}
    if task.get("until") and not reached:
        return False, figures, f"expected {task['until']!r} on the console within {task['seconds']:g} s"
    return True, figures, ""


def duct_branch(rig, reached: bool, task: dict):
    """Seed 002's single right branch run (§5.7): one branch and two ends explored, the
    list empty, and the robot really within 150 mm of its start (hil_tests/test_duct.py)."""
    truth = rig.truth()
    start = rig.plant.start_pose
    off = math.hypot(truth["x_m"] - start[0], truth["y_m"] - start[1])
    explored = "explored: 1 branches found, 2 ends, 0 left" in rig.console
    figures = {"home_off_m": off, "t_end_s": rig.t_us / 1e6, "snags": truth.get("fault_snags", truth.get("snags", 0))}
    if not reached:
        return False, figures, f"expected the exploration to end within {task['seconds']:g} s"
    if not explored:
        line = next((ln for ln in rig.console.splitlines() if "explored:" in ln), "")
        return False, figures, f"expected one branch and two ends explored, got {line.strip()!r}"
    if off > 0.15:
        return False, figures, f"expected home within 150 mm, got {off * 1000:.0f} mm off"
    return True, figures, ""


def pool_mission(rig, reached: bool, task: dict):
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


def no_contact(rig, reached: bool, task: dict):
    """As :func:`generic`, and the robot touched nothing (the rover's room, the vacuum's
    furniture)."""
    ok, figures, message = generic(rig, reached, task)
    contacts = rig.truth().get("contacts", [])
    figures["contacts"] = len(contacts)
    if ok and contacts:
        return False, figures, f"expected no contact, got {len(contacts)}"
    return ok, figures, message


def declared(rig, reached: bool, task: dict):
    """As the rig file's ``[report.judge]`` says: ``console`` (a text the console must
    show), ``no_contact``, ``home_within_m`` (the robot ends this near its start; figure
    ``home_off_m``), ``min_coverage`` (figure ``coverage``); and the ``until`` text, as
    :func:`generic`. Every unmet condition, in that order, is the message (joined by
    ``; ``): a shrink's candidate fails the same way only when it misses the same ones."""
    expect = (rig.app.extra.get("report") or {}).get("judge") or {}
    ok, figures, message = generic(rig, reached, task)
    truth = rig.truth()
    problems = [] if ok else [message]
    if expect.get("console") and expect["console"] not in rig.console:
        problems.append(f"expected {expect['console']!r} on the console")
    if expect.get("no_contact"):
        figures["contacts"] = len(truth.get("contacts", []))
        if figures["contacts"]:
            problems.append(f"expected no contact, got {figures['contacts']}")
    if "home_within_m" in expect:
        x0, y0 = rig.plant.start_pose[:2]
        figures["home_off_m"] = math.hypot(truth["x_m"] - x0, truth["y_m"] - y0)
        if figures["home_off_m"] > expect["home_within_m"]:
            problems.append(f"expected home within {expect['home_within_m']:g} m, got {figures['home_off_m']:.3f} m")
    if "min_coverage" in expect:
        figures["coverage"] = truth.get("coverage_fraction", math.nan)
        if not figures["coverage"] >= expect["min_coverage"]:
            problems.append(f"expected >= {expect['min_coverage']:.0%} covered, got {figures['coverage']:.1%}")
    return not problems, figures, "; ".join(problems)


JUDGES = {
    "generic": generic,
    "declared": declared,
    "duct_branch": duct_branch,
    "pool_mission": pool_mission,
    "no_contact": no_contact,
}
