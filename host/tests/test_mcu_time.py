"""MCU time (docs/mcu-time.md): with ``[board] cpu`` the firmware's compute, counted by the
harness's interpreter (host/core/micropython/hilcount.patch), costs the board CPU's time
in virtual time, the same on any host and any load."""

import json
import subprocess
import textwrap

import pytest

from host.rig.targets import mcutime
from host.tests.conftest import results

# A control loop: ~5 ms of float math per period on an RP2040 (per the model), then the LED
# toggles and the loop sleeps 20 ms. ITERATIONS is sized from the model (below).
CONTROL = """
def control(n):
    x = 0.5
    acc = 0.0
    for i in range(n):
        x = x * 1.0001 + 0.25
        acc += x / (i + 1)
    return acc
"""
"""The step both firmwares below compute (~5 ms of float math, sized by ITERATIONS)."""
LOOP = (
    """
import time
from machine import Pin

led = Pin(2, Pin.OUT)

"""
    + CONTROL
    + """

t_prev = time.ticks_us()
for loop in range(ROUNDS):
    t0 = time.ticks_us()
    control(ITERATIONS)
    t1 = time.ticks_us()
    led.toggle()
    if loop == ROUNDS - 1:
        print("R compute_us", time.ticks_diff(t1, t0))
    time.sleep_ms(20)
"""
)
ROUNDS = 10


def rig_file(folder, cpu, limit_us, iterations):
    folder.mkdir(exist_ok=True)
    main = LOOP.replace("ROUNDS", str(ROUNDS)).replace("ITERATIONS", str(iterations))
    (folder / "main.py").write_text(textwrap.dedent(main))
    (folder / "rig.toml").write_text(
        f'name = "mcu"\n[firmware]\nallow_exit = true\n[board]\nconsole_baud = 0\ncpu = "{cpu}"\n'
        "[board.pins]\nLED = 2\n"
        '[plant]\nbody = "bench"\n[wiring]\nLED = "probe:led"\n'
        f'[budgets.control]\nkind = "compute"\nlimit_us = {limit_us}\n'
    )
    return str(folder / "rig.toml")


def iterations_for(interpreter, cpu: str, target_us: float) -> int:
    """The loop count whose compute costs target_us on cpu (the model, from a counted run)."""
    probe = LOOP.split("t_prev")[0].replace("from machine import Pin", "").replace("led = Pin(2, Pin.OUT)", "")
    probe += "import _hilfast, json\nc0 = _hilfast.counts()\ncontrol(1000)\nc1 = _hilfast.counts()\n"
    probe += "d = {k: (c1[k] - c0[k]) if k != 'ops' else [b - a for a, b in zip(c0[k], c1[k])] for k in c1}\n"
    probe += "print(json.dumps(d))\n"
    out = subprocess.run([str(interpreter), "-c", probe], capture_output=True, text=True, timeout=30, check=True)
    per_1000 = mcutime.CPUS[cpu].charge_us(json.loads(out.stdout))
    return round(1000 * target_us / per_1000)


@pytest.fixture(scope="module")
def iterations():
    from host.core import interpreter

    return iterations_for(interpreter.find(), "rp2040@125MHz", 5000)


@pytest.mark.parametrize(("cpu", "limit_us", "holds"), [
    ("rp2040@125MHz", 4000, False),
    ("rp2040@125MHz", 6000, True),
    ("free", 4000, True),
    ("free", 6000, True),
])  # fmt: skip
def test_5ms_of_math_on_an_rp2040_misses_4ms_holds_6ms_and_free_takes_none(
    make_rig, tmp_path, iterations, cpu, limit_us, holds
):
    rig = make_rig(rig_file(tmp_path / "app", cpu, limit_us, iterations))
    rig.run_for(1)
    rig.stop()
    compute_us = results(rig.console)["compute_us"]
    budget = rig.budgets["control"]
    if cpu == "free":  # compute takes no virtual time; the budget measures wall time (informational)
        assert compute_us == 0, f"compute took virtual time with cpu free: {compute_us} us (console: {rig.console!r})"
        assert budget.wall_clock and budget.limit_text().endswith("wall")
        return
    assert 4500 <= compute_us <= 5500, f"expected ~5000 us of MCU time a loop, the clock moved {compute_us} us"
    assert not budget.wall_clock and budget.limit_text().endswith("on rp2040@125MHz")
    if holds:
        budget.check()
    else:
        with pytest.raises(AssertionError, match="budget control"):
            budget.check()


def test_the_same_seed_gives_a_byte_identical_trace_on_a_loaded_machine(make_rig, tmp_path, iterations):
    """MCU time is counted, never measured: a busy process beside the second run changes
    nothing in the trace; with cpu free the same firmware's trace differs (no compute time)."""
    traces = []
    runs = (("rp2040", "rp2040@125MHz", False), ("rp2040", "rp2040@125MHz", True), ("free", "free", False))
    for folder, cpu, loaded in runs:
        busy = None
        if loaded:  # (a spinning process on this machine's cores while the rig runs)
            busy = subprocess.Popen(["python3", "-c", "while True: pass"])
        try:
            rig = make_rig(rig_file(tmp_path / folder, cpu, 6000, iterations), seed=3, trace=True)
            rig.run_for(0.5)
            rig.stop()
        finally:
            if busy is not None:
                busy.kill()
                busy.wait()
        traces.append((rig.artefacts / "trace.jsonl").read_bytes().split(b"\n", 1)[1])  # (after the header)
    assert len(traces[0]) > 1000, f"expected a trace, got {len(traces[0])} bytes"
    assert traces[0] == traces[1], "the loaded run's trace differs from the quiet one's (MCU time not deterministic)"
    assert traces[0] != traces[2], "the trace with cpu free is the same as with an RP2040's time: compute not charged"


def test_an_interpreter_that_cannot_count_says_compute_is_free(make_rig, tmp_path, iterations, monkeypatch):
    monkeypatch.setenv("HIL_PURE", "1")  # (the shim's pure-Python path, as on a user's own interpreter)
    rig = make_rig(rig_file(tmp_path / "app", "rp2040@125MHz", 6000, iterations))
    rig.run_for(0.5)
    rig.stop()
    said = [ln for ln in rig.console.splitlines() if "compute is free" in ln]
    assert len(said) == 1, f"expected one line saying compute is free, got {said} (console: {rig.console!r})"
    assert results(rig.console)["compute_us"] == 0


CALLBACKS = (
    """
import time
from machine import Timer

"""
    + CONTROL
    + """

def tick(t):
    control(ITERATIONS)


tim = Timer(0)
for sleep_ms in (20, 25):
    tim.init(period=10, callback=tick)
    t0 = time.ticks_us()
    time.sleep_ms(sleep_ms)
    t1 = time.ticks_us()
    tim.deinit()
    print("R slept_%d" % sleep_ms, time.ticks_diff(t1, t0))
    time.sleep_ms(50)
"""
)


def test_a_callbacks_compute_delays_the_main_program_only_when_it_overlaps(make_rig, tmp_path):
    """Timer callbacks of ~3 ms on an RP2040 at 10 and 20 ms: a 20 ms sleep ends once the
    second is done (~23 ms), a 25 ms sleep when it was due (both done by then)."""
    from host.core import interpreter

    cb_iterations = iterations_for(interpreter.find(), "rp2040@125MHz", 3000)
    folder = tmp_path / "app"
    folder.mkdir()
    (folder / "main.py").write_text(textwrap.dedent(CALLBACKS.replace("ITERATIONS", str(cb_iterations))))
    (folder / "rig.toml").write_text(
        'name = "mcu_irq"\n[firmware]\nallow_exit = true\n[board]\nconsole_baud = 0\ncpu = "rp2040@125MHz"\n'
        '[board.pins]\nLED = 2\n[plant]\nbody = "bench"\n[wiring]\nLED = "probe:led"\n'
    )
    rig = make_rig(str(folder / "rig.toml"))
    rig.run_for(0.5)
    rig.stop()
    got = results(rig.console)
    assert 22_500 <= got["slept_20"] <= 23_500, f"expected the 20 ms sleep ~3 ms late, got {got} ({rig.console!r})"
    assert 25_000 <= got["slept_25"] <= 25_100, f"expected the 25 ms sleep to end on time, got {got} ({rig.console!r})"


def test_the_stack_names_the_running_functions(tmp_path):
    """_hilfast.stack(): the firmware's call stack as (file, function, line), outermost first."""
    from host.core import interpreter

    script = tmp_path / "stack.py"
    script.write_text(
        "import _hilfast\n"
        "def inner():\n"
        "    return _hilfast.stack()\n"
        "def outer():\n"
        "    x = 1\n"
        "    return inner()\n"
        "print(outer())\n"
    )
    out = subprocess.run([str(interpreter.find()), str(script)], capture_output=True, text=True, timeout=30)
    want = f"[('{script}', '<module>', 7), ('{script}', 'outer', 6), ('{script}', 'inner', 3)]"
    assert out.stdout.strip() == want, f"expected {want}, got {out.stdout!r} {out.stderr!r}"


def test_the_rig_file_names_the_cpu_or_gets_its_familys(tmp_path, monkeypatch):
    from host.core.errors import ConfigError
    from host.rig.config.rigfile import load_rig

    def cpu_of(board_lines):
        folder = tmp_path / "rig"
        folder.mkdir(exist_ok=True)
        (folder / "main.py").write_text("pass\n")
        (folder / "rig.toml").write_text(
            f'name = "cpu"\n[board]\n{board_lines}\n[board.pins]\nLED = 2\n'
            '[plant]\nbody = "bench"\n[wiring]\nLED = "probe:led"\n'
        )
        return load_rig(folder / "rig.toml").board.cpu

    assert cpu_of('cpu = "esp32s3@240MHz"') == "esp32s3@240MHz"
    assert cpu_of('family = "rpi_pico"') == "free"  # (no default CPU yet: mcutime.DEFAULT_ON)
    monkeypatch.setattr(mcutime, "DEFAULT_ON", True)
    assert cpu_of('family = "rpi_pico"') == "rp2040@125MHz"
    assert cpu_of('family = "rpi_pico2"') == "rp2350@150MHz"
    # (the 3pi+'s _machine is its board's name alone, "Pololu 3pi+ 2040 Robot": its chip from a table)
    assert cpu_of('family = "pololu_3pi_2040_robot"') == "rp2040@125MHz"
    assert cpu_of('family = "sparkfun_xrp_controller"') == "rp2350@150MHz"
    assert cpu_of('family = "esp32"\ncpu = "free"') == "free"
    with pytest.raises(ConfigError, match=r"\[board\] cpu.*expected one of rp2040@125MHz.*got 'rp2040'"):
        cpu_of('cpu = "rp2040"')


def test_callbacks_that_need_more_than_the_cpu_say_the_board_falls_behind(make_rig, tmp_path):
    """A Timer every 2 ms whose callback costs ~3 ms on an RP2040: its ticks come faster
    than they run, so the scheduler's queue fills and later calls are lost (the run says
    so once); the main program's 10 ms sleep runs one callback a pass, as the port's
    mp_hal_delay_ms does, and ends when the one running at its end is done (the third, at
    about 11 ms), then the main program goes on between callbacks, as on the board. (Its
    clock read after the sleep reads later here, 18.5 ms: the few µs it computes before
    the read are charged as one piece, which the queued callbacks preempt, where a board
    runs one at each of its branches, none in those µs: docs/mcu-time.md.)"""
    from host.core import interpreter

    cb_iterations = iterations_for(interpreter.find(), "rp2040@125MHz", 3000)
    main = CALLBACKS.split("tim = Timer(0)")[0].replace("ITERATIONS", str(cb_iterations))
    main += "tim = Timer(0)\ntim.init(period=2, callback=tick)\nt0 = time.ticks_us()\ntime.sleep_ms(10)\n"
    main += "print('R woke', time.ticks_diff(time.ticks_us(), t0))\ntime.sleep_ms(100)\n"
    folder = tmp_path / "app"
    folder.mkdir()
    (folder / "main.py").write_text(textwrap.dedent(main))
    (folder / "rig.toml").write_text(
        'name = "mcu_behind"\n[firmware]\nallow_exit = true\n[board]\nconsole_baud = 0\ncpu = "rp2040@125MHz"\n'
        '[board.pins]\nLED = 2\n[plant]\nbody = "bench"\n[wiring]\nLED = "probe:led"\n'
    )
    rig = make_rig(str(folder / "rig.toml"))
    rig.run_for(0.4)
    rig.stop()
    said = [ln for ln in rig.console.splitlines() if "fall behind" in ln]
    assert len(said) == 1 and "was lost" in said[0], f"expected one line on lost calls, got {said} ({rig.console!r})"
    woke = results(rig.console).get("woke")
    assert woke is not None and 10_000 <= woke <= 20_000, f"expected it on at 10 to 20 ms, got {woke} ({rig.console!r})"


@pytest.mark.parametrize(("edges_per_s", "behind"), [(40_000, True), (1_000, False)])
def test_encoder_handlers_at_40000_edges_a_second_outrun_an_rp2040(tmp_path, monkeypatch, edges_per_s, behind):
    """The encoder bot's pin IRQ handlers (run by _hilfast.apply_state in C) on an RP2040:
    40,000 edges a second need more than its CPU, 1,000 do not."""
    from host.bench import ENCODER_BOT, encoder_firmware
    from host.rig import Recording, Rig, RigSpec

    monkeypatch.setenv("MPYFIL_CPU", "rp2040@125MHz")
    main_dir = encoder_firmware(tmp_path / "fw", edges_per_s, 300)
    spec = RigSpec(str(ENCODER_BOT / "rig.toml"), seed=1, main_dir=main_dir, allow_exit=True)
    with Rig(spec, Recording(artefacts=tmp_path / "run")) as rig:
        rig.run_for(0.6)  # (the main program's first wait ends at 0.5 s: held past it, said then)
        console = rig.console
        shares = rig.cpu_load.record(rig.t_us)["callbacks_share"]
    said = [ln for ln in console.splitlines() if "fall behind" in ln]
    assert bool(said) == behind, f"at {edges_per_s} edges/s expected falling behind: {behind}, the run said {said}"
    # the CPU load view (the report's): the handlers' share of each 100 ms, past 100 % when behind
    assert (max(shares) > 1.0) == behind, f"at {edges_per_s} edges/s the callbacks' share of the CPU: {shares}"
    assert max(shares) > 0.02, f"expected the encoder handlers' compute in the CPU load, got {shares}"


def test_the_report_shows_the_cpu_load_and_the_function_of_the_longest_stretch(make_rig, tmp_path, iterations):
    """The trace folder holds the firmware's busy share of each 100 ms (cpu_load.csv, the
    header's mcu_time) and its longest compute stretch with the code that ran it: a step
    that computes ~5 ms and then writes its output (as a control step does) is named."""
    folder = tmp_path / "app"
    rig_file(folder, "rp2040@125MHz", 6000, iterations)
    main = LOOP.replace("ROUNDS", str(ROUNDS)).replace("ITERATIONS", str(iterations))
    main = main.replace("    return acc\n", "    led.toggle()\n    return acc\n")  # (the write inside the step)
    main = main.replace("    led.toggle()\n    if", "    if")
    (folder / "main.py").write_text(textwrap.dedent(main))
    rig = make_rig(str(folder / "rig.toml"), trace=True, record=True)  # (its trace folder under make test too)
    rig.run_for(0.5)
    rig.stop()
    header = json.loads((rig.artefacts / "header.json").read_text())
    mcu = header["mcu_time"]
    where = f"(trace folder {rig.artefacts})"
    # ~5 ms of compute each ~25 ms period (ten of them, then the firmware ends): about a
    # fifth of each 100 ms busy, then none
    shares = mcu["busy_share"]
    assert len(shares) == 5, f"expected 5 windows of 100 ms in 0.5 s, got {shares} {where}"
    assert all(0.15 <= s <= 0.25 for s in shares[:2]), f"expected ~20 % busy a window, got {shares} {where}"
    assert shares[3:] == [0.0, 0.0], f"expected no compute once the firmware ended, got {shares} {where}"
    rows = (rig.artefacts / "cpu_load.csv").read_text().splitlines()
    head_ok = rows[0] == "t_us,busy_share,callbacks_share" and rows[2].startswith("100000,")
    assert head_ok, f"cpu_load.csv: {rows[:3]} {where}"
    longest = mcu["longest"][0]
    assert 4500 <= longest["compute_us"] <= 5600, f"expected the longest stretch ~5 ms, got {longest} {where}"
    assert "in control" in longest["code"] and "main.py" in longest["code"], (
        f"expected the longest stretch to name the function control of main.py, got {longest['code']!r} {where}"
    )
    assert "_hil" not in longest["code"], f"the shim's own frames in the stretch's code: {longest['code']!r}"
    from host.report.plots import plot_trace

    assert any(p.name == "cpu.png" for p in plot_trace(rig.artefacts, tmp_path / "plots")), "no CPU load plot"


PREEMPT = """
import time
from machine import Timer

CONTROL


def tick(t):
    control(CB_ITERATIONS)


tim = Timer(0)
tim.init(period=2, callback=tick)
t0 = time.ticks_us()
control(ITERATIONS)
t1 = time.ticks_us()
tim.deinit()
print("R computed", time.ticks_diff(t1, t0))
"""


def test_callbacks_that_fire_during_the_main_programs_compute_preempt_it(make_rig, tmp_path, iterations):
    """5 ms of the main program's compute on an RP2040 with a Timer callback of ~0.5 ms
    every 2 ms: the callbacks preempt it (at 2 and 4 ms, and at 6 ms when it is still not
    done), so its 5 ms end 6 to 6.5 ms later, not 5 ms (as when the callbacks ran beside it)."""
    from host.core import interpreter

    cb_iterations = iterations_for(interpreter.find(), "rp2040@125MHz", 500)
    control = CONTROL.lstrip("\n") + "\n\n"
    main = PREEMPT.replace("CONTROL", control).replace("CB_ITERATIONS", str(cb_iterations))
    folder = tmp_path / "app"
    folder.mkdir()
    (folder / "main.py").write_text(main.replace("ITERATIONS", str(iterations)))
    (folder / "rig.toml").write_text(
        'name = "mcu_preempt"\n[firmware]\nallow_exit = true\n[board]\nconsole_baud = 0\ncpu = "rp2040@125MHz"\n'
        '[board.pins]\nLED = 2\n[plant]\nbody = "bench"\n[wiring]\nLED = "probe:led"\n'
    )
    rig = make_rig(str(folder / "rig.toml"))
    rig.run_for(0.1)
    rig.stop()
    got = results(rig.console)["computed"]
    assert 5_900 <= got <= 6_700, f"expected 6,000 to 6,500 us (5 ms, preempted), got {got} ({rig.console!r})"


QUIET = (
    """
import time
"""
    + CONTROL
    + """
for loop in range(30):
    control(ITERATIONS)
    time.sleep_ms(10)
"""
)


def test_waits_the_shim_serves_itself_end_each_compute_stretch(make_rig, tmp_path, iterations):
    """A loop with no output between its sleeps: the shim serves most waits itself (no
    exchange), yet each is the end of a stretch of compute: the compute budget gets one
    value a loop (CPU_RUNS), the longest stretch is one loop's, not a sum of several, and
    the CPU load is spread over the loops' instants."""
    folder = tmp_path / "app"
    rig_file(folder, "rp2040@125MHz", 1000, iterations)
    (folder / "main.py").write_text(textwrap.dedent(QUIET.replace("ITERATIONS", str(round(iterations * 1.1 / 5)))))
    rig = make_rig(str(folder / "rig.toml"), trace=True, record=True)
    rig.run_for(0.5)
    rig.stop()
    stats = rig.budgets["control"].stats()
    where = f"(trace folder {rig.artefacts})"
    assert 29 <= stats["count"] <= 31, f"expected a value a loop (30), got {stats} {where}"
    assert stats["misses"] == stats["count"] and 1000 < stats["max"] < 1400, (
        f"each ~1.1 ms (the first with the start-up): {stats} {where}"
    )
    mcu = json.loads((rig.artefacts / "header.json").read_text())["mcu_time"]
    longest = mcu["longest"][0]["compute_us"]
    assert 1000 < longest < 1400, f"expected the longest stretch one loop's ~1.1 ms, got {longest} us {where}"
    shares = mcu["busy_share"]
    assert all(0.07 <= s <= 0.13 for s in shares[:3]), f"expected ~10 % busy each 100 ms, got {shares} {where}"


@pytest.mark.parametrize("cpu", ["free", "rp2040@125MHz"])
def test_a_line_printed_after_compute_is_stamped_when_it_leaves(run_case, monkeypatch, cpu):
    """On a board a print's text leaves once the compute before it is done: with MCU time the
    console's stamp of each line is that instant, two lines printed between the same two waits
    each with its own; with the CPU free both carry the wait's instant (1 ms)."""
    from host.artefacts.console import stamped_lines

    monkeypatch.setenv("MPYFIL_CPU", cpu)
    rig, r = run_case("print_after_compute", 0.01)
    lines = {line.split()[1]: t for t, line in stamped_lines(rig.artefacts / "console.log") if line.startswith("R ")}
    where = f"(console.log: {lines}; results {r}; artefacts: {rig.artefacts})"
    first, second, elapsed = lines["first"], lines["second"], r["elapsed_us"]
    if cpu == "free":
        assert first == second == 1000 and elapsed == 0, f"expected both lines at 1 ms, no time spent, {where}"
        return
    t0 = lines["elapsed_us"] - elapsed  # (the clock read before the first loop)
    assert t0 < first < second < lines["elapsed_us"], f"expected each line after the compute before it, {where}"
    # (the two loops are alike: each line comes one loop's compute after the one before it)
    assert abs((second - first) - (first - t0)) <= 0.2 * (first - t0), f"expected a loop between the lines, {where}"


def test_prints_under_heap_lock_pay_their_compute_without_allocating(run_case, monkeypatch):
    """A print under micropython.heap_lock() (as a board's print allocates nothing) after
    compute, and a wait after a longer stretch: the clock brought to the print's instant there
    too, the stretch's code sampled where it can be, no MemoryError."""
    monkeypatch.setenv("MPYFIL_CPU", "rp2040@125MHz")
    rig, r = run_case("print_locked", 0.01)
    where = f"(console: {rig.console!r}; artefacts: {rig.artefacts})"
    assert r.get("done") is True and r["locked"] == sum(range(200)) and r["again"] == 3, where
    assert r["after_wait"] == sum(range(200)) - sum(range(400)), where
    assert "MemoryError" not in rig.console, where
