"""A declared mission's progress: percent, rate and time left carried across the chunks
a scenario runs it in, on a terminal and in a log (a line at each tenth)."""

from host.report.progress import MissionProgress


def run_in_chunks(progress, now, chunk_s=60, chunks=60, wall_per_chunk_s=1.0, reports_per_chunk=4):
    """A mission run as ``run_for(chunk_s)`` again and again, the rig reporting a few
    times per chunk (as Rig does, every 0.25 s of wall time and at the chunk's end)."""
    t_us = 0
    for _ in range(chunks):
        end_us = t_us + chunk_s * 1_000_000
        progress(t_us, end_us)
        for k in range(1, reports_per_chunk + 1):
            now[0] += wall_per_chunk_s / reports_per_chunk
            progress(t_us + (end_us - t_us) * k // reports_per_chunk, end_us)
        t_us = end_us


def test_a_declared_mission_carries_its_percent_and_time_left_across_run_for_chunks():
    now, shown = [0.0], []
    progress = MissionProgress("pool rig0", rewrite=shown.append, clock=lambda: now[0], mission_s=3600)
    run_in_chunks(progress, now, chunks=30)  # half the mission: 30 chunks of 60 s, 1 s of wall each
    assert shown[-1] == ("pool rig0: 1800.0 / 3600.0 s simulated (50%), 30.0 s wall, 60x real time, about 30 s left"), (
        shown[-1]
    )
    shares = [int(text.split("(")[1].split("%")[0]) for text in shown]
    assert shares == sorted(shares) and shares[0] <= 2, f"the percent must only grow across chunks: {shares}"


def test_undeclared_chunks_are_missions_of_their_own_as_before():
    now, shown = [0.0], []
    progress = MissionProgress("pool rig0", rewrite=shown.append, clock=lambda: now[0])
    run_in_chunks(progress, now, chunks=10, wall_per_chunk_s=2.0)
    assert shown[-1].startswith("pool rig0: 600.0 / 600.0 s simulated (100%), 2.0 s wall"), shown[-1]


def test_in_a_log_a_declared_mission_writes_a_line_at_each_tenth_the_last_at_its_end():
    now, lines = [0.0], []
    progress = MissionProgress("pool rig0", line=lines.append, clock=lambda: now[0], mission_s=3600)
    run_in_chunks(progress, now, chunks=60)  # 60 s of wall time: a tenth every 6 s
    shares = [text.split("(")[1].split("%")[0] for text in lines]
    assert shares == [str(10 * k) for k in range(1, 11)], lines  # the tenth at 100 % is the end's line
    assert lines[-1].startswith("pool rig0: 3600.0 / 3600.0 s simulated (100%), 60.0 s wall"), lines


def test_the_mission_context_starts_where_the_scenario_is_and_ends_with_the_block():
    now, shown = [0.0], []
    progress = MissionProgress("rig0", rewrite=shown.append, clock=lambda: now[0])
    progress(0, 100_000_000)
    now[0] += 2.0
    progress(100_000_000, 100_000_000)  # a setup run of its own
    with progress.mission(200):
        progress(100_000_000, 160_000_000)
        now[0] += 2.0
        progress(160_000_000, 160_000_000)
    assert shown[-1] == "rig0: 160.0 / 300.0 s simulated (30%), 2.0 s wall, 30x real time, about 5 s left", shown
