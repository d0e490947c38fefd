"""One verdict per budget (host/rig/config/verdicts.py), the same on every surface: the
terminal's summary, the HTML report, the histograms; a miss a passed test did not fail
on is tolerated, with why, never red."""

import re

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from host.report import html, plots, table, views
from host.rig.config import verdicts
from host.rig.config.budgets import LatencyBudget, PeriodBudget

LATENCY = {"budget": "link.latency", "limit": "<= 20000 us", "count": 206, "p50": 3000, "max": 9000, "misses": 1}


def test_a_sample_replaced_before_it_was_read_is_a_tolerated_miss_with_why_on_a_passed_test():
    budget = LatencyBudget("link.latency", "uart", limit_us=20_000)
    budget.sample(0, 1)
    budget.sample(10_000, 2)  # sample 1 never read: a miss at 10 ms, under the limit
    budget.seen(12_000, 2)
    (row,) = verdicts.rows_of([budget], test_failed=False)
    assert (row["misses"], row["replaced"], row["max"]) == (1, 1, 10_000)
    assert row["verdict"] == "tolerated", row
    assert "not checked by the test" in row["why"] and "replaced before the firmware read it" in row["why"], row


def test_a_checked_budget_that_failed_its_test_is_missed_and_one_that_held_is_held():
    late = PeriodBudget("control.period", "probe", period_us=50_000, tolerance_us=1000)
    for t_us in (0, 50_000, 103_000):
        late.event(t_us)
    try:
        late.check()
    except AssertionError:
        pass
    assert verdicts.rows_of([late], test_failed=True)[0]["verdict"] == "missed"
    caught = verdicts.rows_of([late], test_failed=False)[0]
    assert caught["verdict"] == "tolerated" and "expected these misses" in caught["why"], caught
    ok = PeriodBudget("control.period", "probe", period_us=50_000, tolerance_us=1000)
    for t_us in (0, 50_000, 100_000):
        ok.event(t_us)
    ok.check()
    assert verdicts.rows_of([ok], test_failed=True)[0][("verdict")] == "held"


def test_a_tolerated_budget_says_the_tests_reason_and_its_check_passes():
    budget = PeriodBudget("control.period", "probe", period_us=50_000, tolerance_us=1000)
    for t_us in (0, 50_000, 103_000):
        budget.event(t_us)
    budget.tolerate("real time on a shared machine: the scheduler's jitter")
    budget.check()  # does not raise
    (row,) = verdicts.rows_of([budget], test_failed=False)
    assert row["verdict"] == "tolerated" and row["why"] == "real time on a shared machine: the scheduler's jitter"


ROWS = st.fixed_dictionaries(
    {
        "budget": st.sampled_from(["a", "b"]),
        "limit": st.sampled_from(["<= 100 us", "<= 100 us wall", "50000 +- 1000 us"]),
        "count": st.integers(0, 50),
        "misses": st.integers(0, 50),
        "replaced": st.integers(0, 5),
        "checked": st.sampled_from([None, "held", "missed"]),
        "tolerated": st.sampled_from(["", "a reason"]),
    }
)


@given(ROWS, st.booleans())
def test_a_passed_tests_budget_is_never_missed_and_a_verdict_other_than_held_says_why(row, failed):
    verdict, why = verdicts.judge(row, failed)
    assert verdict in verdicts.ORDER
    assert failed or verdict != "missed"
    assert why, (row, verdict)
    assert verdict != "held" or not row["misses"] or row["limit"].endswith("wall")


def judged(rows, failed=False):
    return verdicts.judged(rows, failed)


def test_the_terminal_summary_opens_with_the_headline_and_says_tolerated_with_why_never_missed():
    rows = judged([{"scenario": "test_kp_sweep", **LATENCY, "replaced": 1}])
    rows += judged([{**LATENCY, "scenario": "test_ok", "misses": 0}])
    text = table.format_summary(rows)
    lines = text.splitlines()
    assert lines[0] == ("Budgets held: 1 held, 1 with misses their tests tolerate (why beside each), none missed"), (
        lines[0]
    )
    assert "MISSED" not in text, text
    assert re.search(r"^test_kp_sweep +tolerated link.latency 1/206 \(not checked by the test; the miss", text, re.M)


def test_the_terminal_summary_says_missed_for_a_failed_tests_checked_budget():
    rows = judged([{"scenario": "test_late", **LATENCY, "checked": "missed"}], failed=True)
    text = table.format_summary(rows, {"test_late"})
    assert text.splitlines()[0].startswith("Budgets MISSED: 1 missed"), text
    assert "MISSED link.latency 1/206, max 9000 (<= 20000 us)" in text and "missed" in text.splitlines()[-1], text


def test_the_terminal_summary_never_cuts_a_name_and_keeps_to_the_width():
    names = [f"test_square_closes_within_20mm_after_three_left_turns[{board}]" for board in ("rpi_pico", "esp32")]
    rows = [r for name in names for r in judged([{**LATENCY, "scenario": name, "misses": 0}])]
    text = table.format_summary(rows, width=80)
    assert all(name in text for name in names), text
    assert max(map(len, text.splitlines())) <= 80, text
    assert "..." not in text


def test_the_report_shows_each_verdict_with_why_and_the_headline_at_the_top(tmp_path):
    rig = html.RigResult("rig0", tmp_path, judged([{**LATENCY, "replaced": 1}]))
    s = html.Scenario("test_kp_sweep", "hil_tests/test_duct.py::test_kp_sweep", "passed", rigs=[rig])
    page = html.render([s], base=tmp_path)
    assert 'id="budgets">Budgets held: 0 held, 1 with misses their tests tolerate' in page, page[:2000]
    assert '<span class="v tolerated">1 tolerated</span>' in page
    assert "link.latency 1/206: not checked by the test; the miss is a sample replaced" in page
    assert 'class="missed"' not in page and ">1 missed<" not in page
    assert "budget misses (enforced)" not in page


def test_the_report_groups_scenarios_by_app_lists_skipped_tests_and_shows_the_tests_parameters(tmp_path):
    def scenario(name, app, options=None):
        header = {"app": app, "board": "b", "seed": 1, "mode": "lockstep", "t_end_us": 1_000_000}
        header["spec"] = {"options": options or {}}
        return html.Scenario(name, f"t.py::{name}", "passed", rigs=[html.RigResult("rig0", tmp_path, header=header)])

    order = [
        scenario("test_b", "rover"),
        scenario("test_kp", "duct", {"world": "bench_duct", "link.script": [[0, "K 25"]]}),
        scenario("test_a", "rover"),
    ]
    page = html.render(order, base=tmp_path, skipped=[("t.py::test_c", "needs a board")])
    assert page.index('id="app-duct"') < page.index('id="app-rover"'), "apps in order"
    assert page.index(">test_a<") < page.index(">test_b<"), "a group's scenarios by test id, not completion"
    assert "link.script=[[0, &quot;K 25&quot;]]" in page, "the test's parameters in the rig's header"
    assert "<code>t.py::test_c</code>: needs a board" in page


def test_a_set_of_boards_is_grouped_under_the_sets_name_not_its_first_boards(tmp_path):
    def board(name):
        header = {"app": f"two_board_rover.{name}", "spec": {"app": f"/x/rig.toml::{name}"}, "wired": ["link.a"]}
        header.update(board="b", seed=1, mode="lockstep", t_end_us=1_000_000)
        return html.RigResult(f"boards0.{name}", tmp_path, header=header)

    plain = {"board": "b", "seed": 1, "mode": "lockstep", "t_end_us": 1_000_000, "spec": {"app": "/x/rig.toml"}}
    one = html.RigResult("rig0", tmp_path, header={"app": "pico.bot", **plain})
    page = html.render(
        [
            html.Scenario("test_set", "t.py::test_set", "passed", rigs=[board("motor"), board("nav")]),
            html.Scenario("test_one", "t.py::test_one", "passed", rigs=[one]),
        ],
        base=tmp_path,
    )
    assert 'id="app-two-board-rover"' in page and 'id="app-two-board-rover-motor"' not in page, page[:3000]
    assert 'id="app-pico-bot"' in page, "an app's own dotted name is kept"


def test_the_reports_images_are_files_beside_it_not_inline(tmp_path):
    plot = tmp_path / "build" / "rig0" / "plots" / "timing.png"
    plot.parent.mkdir(parents=True)
    plot.write_bytes(b"\x89PNG")
    rig = html.RigResult("rig0", plot.parent.parent, plots=[plot])
    page = html.render([html.Scenario("t", "t.py::t", "passed", rigs=[rig])], base=tmp_path)
    assert 'src="build/rig0/plots/timing.png"' in page and "data:" not in page


def histogram_title(record: dict) -> tuple[str, tuple]:
    fig = plots.Figure()
    ax = fig.add_subplot()
    plots._budget_histogram(ax, record)
    return ax.get_title(), ax.title.get_color()


def test_a_histograms_title_and_colour_say_its_verdict():
    record = {
        "name": "link.latency",
        "limit_us": 20_000,
        "histogram_us": [[3000, 205], [10_000, 1]],
        "stats": {**LATENCY, "p99": 3000, "max": 10_000},
        "replaced": 1,
        "verdict": "tolerated",
    }
    title, colour = histogram_title(record)
    assert title.startswith("link.latency: tolerated, 1 miss (all replaced before read) of 206"), title
    assert colour == plots.TOLERATED_COLOUR
    title, colour = histogram_title({**record, "verdict": "missed"})
    assert title.startswith("link.latency: missed") and colour == plots.MISS_COLOUR
    held = {**record, "stats": {**record["stats"], "misses": 0}, "replaced": 0, "verdict": "held"}
    assert histogram_title(held)[1] == plots.OK_COLOUR


def test_a_signals_panels_legend_covers_none_of_its_lines():
    """The lab robot's heading after three left turns ends top right, where a legend in
    the corner sat over the square's last leg."""
    t_s = np.linspace(0, 27, 541)
    heading = np.degrees(np.minimum(t_s // 6.75, 3) * np.pi / 2)
    panel = views.Panel("Heading: dead reckoning against the truth", "heading (deg)")
    panel.lines.append(views.Line("true heading", t_s, heading))
    panel.lines.append(views.Line("heading by dead reckoning (firmware)", t_s, heading + 1, "points"))
    fig = plots.Figure(figsize=(12, 3))
    fig.subplots_adjust(right=1 - plots.LEGEND_WIDTH_IN / 12)
    ax = fig.add_subplot()
    plots._draw_panel(ax, panel, [], 27.0)
    plots.FigureCanvasAgg(fig).draw()
    box = ax.get_legend().get_window_extent()
    points = ax.transData.transform(np.column_stack([t_s, heading]))
    inside = (points[:, 0] >= box.x0) & (points[:, 0] <= box.x1) & (points[:, 1] >= box.y0) & (points[:, 1] <= box.y1)
    assert not inside.any(), f"{inside.sum()} points of the heading under the legend {box}"
    assert box.x1 <= fig.bbox.x1 and box.y0 >= fig.bbox.y0, f"the legend {box} leaves the figure {fig.bbox}"


def test_a_record_no_test_judged_shows_its_misses_amber_not_red():
    verdict, colour = plots.budget_verdict({"stats": {"misses": 2}})
    assert verdict == "2 misses (no test judged them)" and colour == plots.TOLERATED_COLOUR
