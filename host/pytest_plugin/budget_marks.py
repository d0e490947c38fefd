"""A test's own limits for timing budgets (docs/budgets.md, "A test's own limit"):

    @pytest.mark.hil_budget("sonar.latency", max_ms=20)
    @pytest.mark.hil_budget("control.period", tolerance_us=200)
    def test_...(make_rig): ...

or ``make_rig(app, budget_limits={"sonar.latency": {"max_ms": 20}})`` for one rig. For a set of
boards (``make_boards``, docs/multi-board.md) a budget across boards goes by its name, a board's
own as ``<board>:<name>`` (``@pytest.mark.hil_budget("motor:speed_loop", tolerance_us=500)``). ``max``
is the largest value that holds (a period budget's band becomes period ± (max − period));
``tolerance`` is a period budget's ± band. Set before the rig starts, so every value is
judged by it, ``check()`` and the tables included.
"""

from host.core.errors import ConfigError
from host.rig.config.budgets import PeriodBudget

MARK = "hil_budget"
MARK_HELP = (
    f"{MARK}(name, max_ms=|max_us=, tolerance_ms=|tolerance_us=): this test's limit for one timing "
    "budget of its rigs (docs/budgets.md)"
)
SCALE_US = {"us": 1, "ms": 1000, "s": 1_000_000}
KINDS = ("max", "tolerance")


def marked_limits(item) -> dict[str, dict[str, int]]:
    """The test's ``hil_budget`` marks as name -> {"max_us"/"tolerance_us": value}; a mark
    nearer the test (function over class over module) wins."""
    limits: dict[str, dict[str, int]] = {}
    for mark in reversed(list(item.iter_markers(MARK))):
        if len(mark.args) != 1 or not isinstance(mark.args[0], str):
            raise ConfigError(f"@pytest.mark.{MARK}: expected one budget name, got {mark.args!r} ({MARK_HELP})")
        limits.setdefault(mark.args[0], {}).update(in_us(mark.args[0], mark.kwargs, f"@pytest.mark.{MARK}"))
    return limits


def in_us(name: str, given: dict, where: str) -> dict[str, int]:
    """{"max_ms": 20} -> {"max_us": 20000}, every key checked."""
    out = {}
    for key, value in given.items():
        kind, _, unit = key.rpartition("_")
        if kind not in KINDS or unit not in SCALE_US:
            raise ConfigError(
                f"{where}({name!r}): unknown limit {key!r}; expected max_ms, max_us, tolerance_ms or tolerance_us"
            )
        if isinstance(value, bool) or not isinstance(value, (int, float)) or value < 0:
            raise ConfigError(f"{where}({name!r}): {key} must be a number >= 0, got {value!r}")
        out[f"{kind}_us"] = round(value * SCALE_US[unit])
    if not out:
        raise ConfigError(f"{where}({name!r}): expected a limit (max_ms=..., tolerance_us=...), got none")
    return out


def apply(rig, limits: dict[str, dict[str, int]], where: str) -> None:
    """Set each named budget of ``rig`` to its limits; a name the rig has no budget of,
    or a limit its kind has not, is a ConfigError that lists what there is."""
    for name, limit in limits.items():
        budget = rig.budgets.get(name)
        if budget is None:
            known = ", ".join(sorted(rig.budgets)) or "none"
            raise ConfigError(f"{where}: no budget {name!r} on the {rig.app.name} rig (its budgets: {known})")
        _set(budget, where, **limit)


def apply_to_boards(boards, limits: dict[str, dict[str, int]], where: str) -> None:
    """Set each named budget of a set of boards (a :class:`~host.rig.loop.boardset.BoardSet`) to
    its limits: a budget across boards by its name, a board's own as ``<board>:<name>``; a
    name the set has no budget of is a ConfigError that lists what there is."""
    for name, limit in limits.items():
        budget = boards.budgets.get(name)
        board, _, own = name.partition(":")
        if budget is None and own and board in boards.rigs:
            budget = getattr(boards.rigs[board], "budgets", {}).get(own)
        if budget is None:
            own_budgets = [f"{b}:{n}" for b, rig in boards.rigs.items() for n in sorted(getattr(rig, "budgets", {}))]
            known = ", ".join([*sorted(boards.budgets), *own_budgets]) or "none"
            raise ConfigError(
                f"{where}: no budget {name!r} on the {boards.spec.name} boards (their budgets: {known}; "
                f"a board's own as <board>:<name>)"
            )
        _set(budget, where, **limit)


def _set(budget, where: str, max_us: int | None = None, tolerance_us: int | None = None) -> None:
    if not isinstance(budget, PeriodBudget):
        if tolerance_us is not None:
            raise ConfigError(f"{where}: budget {budget.name!r} has a limit, not a period: set max_ms or max_us")
        budget.limit_us = max_us
        return
    if max_us is not None:
        if max_us < budget.period_us:
            raise ConfigError(
                f"{where}: budget {budget.name!r}: max {max_us} us is under its period {budget.period_us} us"
            )
        tolerance_us = (
            max_us - budget.period_us if tolerance_us is None else min(tolerance_us, max_us - budget.period_us)
        )
    budget.tolerance_us = tolerance_us
    budget.limit_us = budget.period_us + tolerance_us
