"""How a campaign's run is judged: each judge reads the finished rig (console, ground
truth, budgets) and gives (passed, figures, message). The figures are numbers, the
scenario's own (coverage, mission time, distance from home); the message says why a run
failed. ``docs/campaigns.md`` lists them. The generic judges are here; a robot's own
(the duct robot's ``duct_branch``, the pool cleaner's ``pool_mission``, a user's) are
catalogue entries (:class:`sim_plant.catalogue.base.Judge`), found as parts are."""

import math

from host.rig.config.app import Judge
from sim_plant import catalogue


def generic(rig, reached: bool, task: dict):
    """Passes when the run reached its ``until`` text (if it has one)."""
    figures = {"t_end_s": rig.t_us / 1e6}
    if task.get("until") and not reached:
        return False, figures, f"expected {task['until']!r} on the console within {task['seconds']:g} s"
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
    report = rig.app.run.report
    expect = (report.judge if report is not None else None) or Judge()
    ok, figures, message = generic(rig, reached, task)
    truth = rig.truth()
    problems = [] if ok else [message]
    if expect.console and expect.console not in rig.console:
        problems.append(f"expected {expect.console!r} on the console")
    if expect.no_contact:
        figures["contacts"] = len(truth.get("contacts", []))
        if figures["contacts"]:
            problems.append(f"expected no contact, got {figures['contacts']}")
    if expect.home_within_m is not None:
        x0, y0 = rig.plant.start_pose[:2]
        figures["home_off_m"] = math.hypot(truth["x_m"] - x0, truth["y_m"] - y0)
        if figures["home_off_m"] > expect.home_within_m:
            problems.append(f"expected home within {expect.home_within_m:g} m, got {figures['home_off_m']:.3f} m")
    if expect.min_coverage is not None:
        figures["coverage"] = truth.get("coverage_fraction", math.nan)
        if not figures["coverage"] >= expect.min_coverage:
            problems.append(f"expected >= {expect.min_coverage:.0%} covered, got {figures['coverage']:.1%}")
    return not problems, figures, "; ".join(problems)


JUDGES = {"generic": generic, "declared": declared, "no_contact": no_contact}
"""The generic judges (any robot)."""


def judges() -> dict:
    """Every judge by name: the generic ones, then the catalogue's (ours and a user's)."""
    found = dict(JUDGES)
    for kind, cls in catalogue.judges().items():
        found.setdefault(kind, cls({}).judge)
    return found


def figures_of(name: str) -> tuple | None:
    """A catalogue judge's own figures (what its campaign is ranked by), or None."""
    cls = catalogue.judges().get(name)
    return tuple(cls.FIGURES) if cls else None
