"""One verdict per timing budget, the same wherever it is shown (the terminal's table,
the HTML report, the JUnit properties, the histograms): what the test made of the
budget, given how the test ended.

===============  ======================================================  ======
verdict          when                                                    colour
===============  ======================================================  ======
``held``         every value within the limit                            green
``tolerated``    misses the test did not fail on, and why: the test's    amber
                 :meth:`~host.rig.config.budgets.Budget.tolerate` reason, or
                 "not checked by the test" (and how many were samples
                 replaced before they were read), or a miss the test
                 expected (its ``check()`` raised and was caught)
``missed``       the test checked the budget and failed on its misses    red
``info``         wall-clock time: informational in lockstep runs         grey
``unmeasured``   no value (a budget the run never exercised)             grey
===============  ======================================================  ======

A passed test's budgets are never ``missed``. ``docs/budgets.md``, "Verdicts".
"""

import json
from pathlib import Path

from host.artefacts import integrity
from host.artefacts.folder import reseal_file

HELD, TOLERATED, MISSED, INFO, UNMEASURED = "held", "tolerated", "missed", "info", "unmeasured"
ORDER = (MISSED, TOLERATED, HELD, INFO, UNMEASURED)
"""Worst first: the order a summary names them in."""
REPLACED_WHY = "replaced before the firmware read it, a miss by definition (see docs/budgets.md)"


def judge(row: dict, test_failed: bool) -> tuple[str, str]:
    """(verdict, why) of one budget row: its statistics with its ``judgement()``."""
    if row.get("wall_clock") or "wall" in str(row.get("limit", "")):
        return INFO, "wall-clock time: informational in lockstep runs"
    if not row.get("count"):
        if row.get("checked") == MISSED and test_failed:
            return MISSED, "the test checked it and failed: no values measured"
        return UNMEASURED, "no values measured"
    misses = row.get("misses") or 0
    if not misses:
        return HELD, "checked by the test" if row.get("checked") else "not checked by the test"
    return _judge_misses(row, misses, test_failed)


def _judge_misses(row: dict, misses: int, test_failed: bool) -> tuple[str, str]:
    detail = replaced_text(row.get("replaced") or 0, misses)
    if row.get("tolerated"):
        return TOLERATED, _join(row["tolerated"], detail)
    if row.get("checked") == MISSED:
        if test_failed:
            return MISSED, _join(
                f"the test checked it and failed: {misses} of {row['count']} outside {row['limit']}", detail
            )
        return TOLERATED, _join("the test expected these misses (its check() raised and the test went on)", detail)
    why = "not checked by the test" + (", which failed on something else" if test_failed else "")
    return TOLERATED, _join(why, detail)


def replaced_text(replaced: int, misses: int) -> str:
    """``the miss is a sample replaced before the firmware read it (...)``, or ""."""
    if not replaced:
        return ""
    if replaced == misses:
        which = "the miss is a sample" if misses == 1 else "all misses are samples"
    else:
        which = f"{replaced} of the misses are {'a sample' if replaced == 1 else 'samples'}"
    return f"{which} {REPLACED_WHY}"


def _join(*parts: str) -> str:
    return "; ".join(p for p in parts if p)


def judged(rows: list[dict], test_failed: bool) -> list[dict]:
    """The rows with their ``verdict`` and ``why``."""
    out = []
    for row in rows:
        verdict, why = judge(row, test_failed)
        out.append({**row, "verdict": verdict, "why": why})
    return out


def rows_of(budgets, test_failed: bool) -> list[dict]:
    """A stopped rig's budgets (those that measured anything) as judged rows."""
    return judged([{**b.stats(), **b.judgement()} for b in budgets if b.count], test_failed)


def verdict_of(row: dict) -> str:
    """A row's verdict: its own, or (a row from before verdicts) judged as a passed test's."""
    return row.get("verdict") or judge(row, False)[0]


def counts(rows: list[dict]) -> dict[str, int]:
    """verdict -> how many rows have it, worst first."""
    found: dict[str, int] = {}
    for row in rows:
        v = verdict_of(row)
        found[v] = found.get(v, 0) + 1
    return {v: found[v] for v in ORDER if v in found}


def headline(rows: list[dict]) -> tuple[str, str]:
    """(the session's budget verdict, one line saying it): did the budgets hold?"""
    c = counts(rows)
    if not rows:
        return HELD, "Budgets: none measured"
    held, tolerated, missed = c.get(HELD, 0), c.get(TOLERATED, 0), c.get(MISSED, 0)
    extra = f"; {c[INFO]} wall-clock informational" if c.get(INFO) else ""
    if missed:
        return (
            MISSED,
            f"Budgets MISSED: {missed} missed (their tests failed), {tolerated} tolerated, {held} held{extra}",
        )
    if tolerated:
        return (
            TOLERATED,
            f"Budgets held: {held} held, {tolerated} with misses their tests tolerate (why beside each), "
            f"none missed{extra}",
        )
    return HELD, f"Budgets held: all {held} held{extra}"


def stamp(folder, rows: list[dict]) -> None:
    """Write each row's verdict and why into the trace folder's ``budgets.json`` (its
    plots read them there); nothing when the folder has none."""
    if not folder:
        return
    path = Path(folder) / "budgets.json"
    if not path.is_file():
        return
    by_name = {row["budget"]: row for row in rows}
    records = json.loads(path.read_text(encoding="utf-8"))
    for record in records:
        row = by_name.get(record.get("name"))
        if row is not None:
            record["verdict"], record["why"] = row["verdict"], row["why"]
    integrity.write_text(path, json.dumps(records, indent=1))
    reseal_file(Path(folder), path.name)  # (an edit of the harness's own: the seal follows it)
