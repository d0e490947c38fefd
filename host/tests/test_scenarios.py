"""Wokwi automation scenarios in virtual time (docs/wokwi-scenarios.md): each step kind
passing and failing with its line and what was seen, the run's timeout in simulated
time, bad files refused in one line (exit 2), the CLI's exit codes, a pytest item per
``*.test.yaml`` in JUnit, and the parts' controls kept across the plant's rewinds.
The passing projects are ``host/tests/wokwi_scenarios/*/*.test.yaml`` (collected as tests
themselves); the failing ones are copies of them here, in a temporary folder."""

import shutil
import subprocess
import sys
import textwrap
import time
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from host.cli import main
from host.scenario import ScenarioError, StepFailed, load_scenario, run_scenario
from host.scenario.scenario import parse_time_us
from sim_plant.catalogue.assembly import assemble
from sim_plant.controls import ControlError

PROJECTS = Path(__file__).parent / "wokwi_scenarios"
HEADER = "name: 't'\nversion: 1\nauthor: 'mpy-fil'\n"


def project(tmp_path: Path, name: str, steps: str, extra: str = "") -> Path:
    """A copy of one of our scenario projects with a scenario of ``steps`` (YAML);
    the scenario file's path."""
    folder = tmp_path / name
    shutil.copytree(PROJECTS / name, folder, ignore=shutil.ignore_patterns("*.test.yaml", "build"))
    path = folder / "x.test.yaml"
    path.write_text(HEADER + extra + "steps:\n" + textwrap.indent(textwrap.dedent(steps).lstrip("\n"), "  "))
    return path


def failure(path: Path, **kwargs) -> str:
    with pytest.raises(StepFailed) as caught:
        run_scenario(path, out=path.parent.parent / "out", **kwargs)  # (beside the project, not in it)
    return str(caught.value)


# -- parsing ------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "us"), [("500ms", 500_000), ("2s", 2_000_000), ("1.5 s", 1_500_000), ("30us", 30), ("0", 0)]
)
def test_times_read_as_wokwi_reads_them(text, us):
    assert parse_time_us(text, "delay") == us


@pytest.mark.parametrize(
    ("steps", "message"),
    [
        ("- delay: 500\n", r"x.test.yaml:5: delay: missing units: 500"),
        ("- delay: 1s\n- wait-serail: ready\n", r"x.test.yaml:6: unknown step 'wait-serail'"),
        ("- expect-pin:\n    part-id: led1\n    value: 1\n", r"x.test.yaml:5: expect-pin: pin: missing"),
        ("- expect-pin: {part-id: led1, pin: A, value: 2}\n", r"x.test.yaml:5: expect-pin: value: expected 0 or 1"),
        ("- write-serial: [1, 300]\n", r"x.test.yaml:5: write-serial: expected a string or a list of byte values"),
        ("- set-control: {part-id: btn1, control: pressed}\n", r"x.test.yaml:5: set-control: value: missing"),
    ],
)
def test_a_bad_step_is_refused_with_its_line(tmp_path, steps, message):
    path = tmp_path / "x.test.yaml"
    path.write_text(HEADER + "steps:\n" + textwrap.indent(steps, "  "))
    with pytest.raises(ScenarioError, match=message):
        load_scenario(path)


def test_steps_keep_their_lines_and_the_file_its_timeout(tmp_path):
    path = tmp_path / "x.test.yaml"
    path.write_text(HEADER + "timeout: 90s\nsteps:\n  - delay: 1s\n\n  - wait-serial: hi\n")
    scenario = load_scenario(path)
    assert [(s.kind, s.line) for s in scenario.steps] == [("delay", 6), ("wait-serial", 8)]
    assert scenario.timeout_us == 90_000_000


# -- each step, passing and failing ---------------------------------------------------


def test_wait_serial_that_never_comes_names_its_line_and_the_last_serial_lines(tmp_path):
    path = project(tmp_path, "button_irq", "- wait-serial: ready\n- wait-serial: 'Button pressed 1'\n", "timeout: 2s\n")
    message = failure(path)
    assert "x.test.yaml:7: step wait-serial 'Button pressed 1' failed at virtual t=2.000000 s" in message
    assert "timeout 2 simulated s" in message
    assert "last serial lines:\n  ready" in message
    out = path.parent.parent / "out"
    assert f"artefacts: {out}" in message and (out / "console.log").is_file()


def test_wait_serial_passes_over_a_line_printed_before_it_began_as_wokwi_does(tmp_path):
    steps = """
    - wait-serial: ready
    - set-control: {part-id: btn1, control: pressed, value: 1}
    - delay: 100ms
    - wait-serial: 'Button pressed 1'
    """
    message = failure(project(tmp_path, "button_irq", steps, "timeout: 1s\n"))
    assert "x.test.yaml:9: step wait-serial 'Button pressed 1' failed at virtual t=1.000000 s" in message
    assert "last serial lines:\n  ready\n  Button pressed 1" in message  # (printed before the step began)


def test_expect_pin_that_differs_says_the_level_it_saw(tmp_path):
    steps = """
    - wait-serial: ready
    - expect-pin: {part-id: led1, pin: A, value: 1}
    """
    message = failure(project(tmp_path, "button_irq", steps))
    assert "x.test.yaml:6: step expect-pin led1:A == 1 failed at virtual t=0.001000 s" in message
    assert "led1:A (led1.in) is 0, expected 1" in message


def test_wait_pin_times_out_in_simulated_time_with_the_level_it_saw(tmp_path):
    steps = """
    - wait-serial: ready
    - wait-pin: {part-id: led1, pin: A, value: 1, timeout: 250ms}
    """
    message = failure(project(tmp_path, "button_irq", steps))
    assert "x.test.yaml:6: step wait-pin led1:A == 1 (timeout 250ms) failed at virtual t=0.251000 s" in message
    assert "still 0 when its timeout came, expected 1" in message


def test_a_button_press_set_by_set_control_is_seen_by_the_firmwares_irq(tmp_path):
    steps = """
    - wait-serial: ready
    - set-control: {part-id: btn1, control: pressed, value: 1}
    - wait-pin: {part-id: led1, pin: A, value: 1, timeout: 20ms}
    - set-control: {part-id: btn1, control: pressed, value: 0}
    - expect-pin: {part-id: btn1, pin: out, value: 0}
    - delay: 1ms
    - expect-pin: {part-id: btn1, pin: out, value: 1}
    """
    outcome = run_scenario(project(tmp_path, "button_irq", steps), out=tmp_path / "out")
    waited = outcome.results[2]
    assert waited.end_us - waited.t_us <= 11_000  # the firmware's 10 ms loop and a 1 ms look
    assert "Button pressed 1" in (tmp_path / "out" / "console.log").read_text()


def test_an_unknown_control_is_one_line_naming_the_parts_controls_before_the_run(tmp_path, capsys):
    path = project(tmp_path, "hcsr04", "- set-control: {part-id: ultrasonic1, control: range, value: 10}\n")
    assert main(["scenario", str(path), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert "x.test.yaml:5: set-control: ultrasonic1 (hcsr04) has no control 'range' (controls: distance)" in err
    assert not (tmp_path / "out").exists()


def test_a_control_value_out_of_bounds_and_an_unknown_part_are_refused(tmp_path):
    path = project(tmp_path, "hcsr04", "- set-control: {part-id: ultrasonic1, control: distance, value: 900}\n")
    with pytest.raises(ScenarioError, match=r"x.test.yaml:5: set-control: ultrasonic1 \(hcsr04\) distance: expected"):
        run_scenario(path, out=tmp_path / "out")
    path.write_text(HEADER + "steps:\n  - expect-pin: {part-id: servo9, pin: PWM, value: 1}\n")
    with pytest.raises(ScenarioError, match=r"no part or probe 'servo9' on the rig \(has: .*led1.*ultrasonic1"):
        run_scenario(path, out=tmp_path / "out")


def test_write_serial_to_a_firmware_that_ended_fails_with_its_line(tmp_path):
    path = project(tmp_path, "serial_echo", "- delay: 10ms\n- write-serial: 'on'\n")
    (path.parent / "main.py").write_text("print('bye')\n")
    message = failure(path)
    assert "write-serial" in message and "the firmware is not running" in message and "x.test.yaml:6" in message


def test_a_delay_past_the_timeout_fails_at_the_timeout(tmp_path):
    message = failure(project(tmp_path, "serial_echo", "- delay: 5s\n"), timeout_us=3_000_000)
    assert "x.test.yaml:5: step delay 5s failed at virtual t=3.000000 s" in message


# -- time -----------------------------------------------------------------------------


def test_a_minute_of_simulated_time_takes_a_few_wall_seconds(tmp_path):
    """Wokwi bounds a scenario by real time (at best 1x): this one's simulated minute
    runs far faster, with the firmware asking on its console all the while."""
    steps = """
    - wait-serial: ready
    - delay: 60s
    - write-serial: "on\\n"
    - wait-serial: ok on
    """
    t0 = time.perf_counter()
    outcome = run_scenario(project(tmp_path, "serial_echo", steps, "timeout: 90s\n"), out=tmp_path / "out")
    wall_s = time.perf_counter() - t0
    assert 60.0 < outcome.t_end_us / 1e6 < 60.01
    assert wall_s < 15, f"60 simulated s took {wall_s:.1f} wall s"


def test_the_default_timeout_is_wokwis_30_simulated_seconds(tmp_path):
    message = failure(project(tmp_path, "serial_echo", "- wait-serial: never printed\n"))
    assert "failed at virtual t=30.000000 s" in message and "timeout 30 simulated s" in message


# -- the command and pytest -------------------------------------------------------------


def test_the_command_prints_each_step_with_its_virtual_time_and_exits_0_1_2(tmp_path, capsys):
    good = project(
        tmp_path,
        "hcsr04",
        "- set-control: {part-id: ultrasonic1, control: distance, value: 77}\n- wait-serial: 'Distance: 77 cm'\n",
    )
    assert main(["scenario", str(good), "--out", str(tmp_path / "a")]) == 0
    out = capsys.readouterr().out
    assert "[   0.000000 s] line 5: set-control ultrasonic1.distance = 77" in out
    assert "line 6: wait-serial 'Distance: 77 cm'" in out and "pass: t: 2 steps" in out
    assert main(["scenario", str(good), "--timeout", "1ms", "--out", str(tmp_path / "b")]) == 1
    err = capsys.readouterr().err
    assert err.startswith("FAIL ") and "x.test.yaml:6" in err
    assert main(["scenario", str(tmp_path / "none.test.yaml")]) == 2


def test_each_scenario_file_is_a_pytest_item_with_its_result_in_junit(tmp_path):
    passing = project(tmp_path, "button_irq", "- wait-serial: ready\n")
    failing = passing.with_name("bad.test.yaml")
    failing.write_text(HEADER + "timeout: 1s\nsteps:\n  - wait-serial: ready\n  - wait-serial: never\n")
    junit = tmp_path / "junit.xml"
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "pytest",
            "-q",
            "-p",
            "no:cacheprovider",
            "-p",
            "no:xdist",
            str(passing.parent),
            f"--junitxml={junit}",
            "--rootdir",
            str(tmp_path),
        ],
        capture_output=True,
        text=True,
        timeout=120,
        cwd=tmp_path,
    )
    assert done.returncode == 1, done.stdout + done.stderr
    cases = {c.get("classname"): c for c in ET.parse(junit).getroot().iter("testcase")}
    assert set(cases) == {"button_irq.x.test.yaml", "button_irq.bad.test.yaml"}, cases
    assert cases["button_irq.x.test.yaml"].find("failure") is None
    message = cases["button_irq.bad.test.yaml"].find("failure").text
    assert "bad.test.yaml:7: step wait-serial 'never' failed at virtual t=1.000000 s" in message
    assert "Traceback" not in message and "artefacts: " in message and "last serial lines:\n  ready" in message
    props = {p.get("name"): p.get("value") for p in cases["button_irq.x.test.yaml"].iter("property")}
    assert props["scenario.steps"] == "1" and props["rig0.artefacts"]


# -- controls in the plant -------------------------------------------------------------


def test_a_control_set_before_a_rewind_comes_again_when_the_plant_passes_it():
    plant = assemble({"body": "bench", "parts": [{"kind": "button", "name": "btn1"}]})
    plant.reset(0)
    plant.advance_to(1_000)
    snap = plant.snapshot()
    plant.advance_to(5_000)
    plant.set_control("btn1", "pressed", 1)
    assert plant.advance_to(6_000) == [(5_000, "btn1.out", 0)]
    plant.restore(snap)  # (a handler's output inside a speculative batch)
    assert plant.advance_to(6_000) == [(5_000, "btn1.out", 0)]
    assert plant.output("btn1.out") == 0


def test_an_active_high_button_reads_1_pressed_and_a_part_without_controls_says_so():
    plant = assemble(
        {
            "body": "bench",
            "parts": [{"kind": "button", "name": "b", "active_low": False}, {"kind": "probe", "name": "led1"}],
        }
    )
    plant.reset(0)
    plant.set_control("b", "pressed", 1)
    assert plant.advance_to(10) == [(0, "b.out", 1)]
    with pytest.raises(ControlError, match=r"led1 \(probe\) has no control 'pressed' \(controls: none\)"):
        plant.set_control("led1", "pressed", 1)


def test_a_board_pin_is_read_by_its_wokwi_name_whatever_the_board_part_is_called(tmp_path):
    steps = """
    - wait-serial: ready
    - expect-pin: {part-id: esp, pin: D2, value: 0}
    - expect-pin: {part-id: esp, pin: D4, value: 1}
    - expect-pin: {part-id: esp, pin: D2, value: 1}
    """
    message = failure(project(tmp_path, "button_irq", steps))
    assert "x.test.yaml:8: step expect-pin esp:D2 == 1" in message and "esp:D2 (led1.in) is 0" in message


def test_sys_stdin_reads_wait_for_write_serial_in_virtual_time(tmp_path):
    """readline() that blocks before anything is typed, select.poll on sys.stdin, a read
    of n bytes and a read of what is there: each waits in virtual time, as on a board."""
    steps = """
    - delay: 1s
    - write-serial: "hi\\n"
    - wait-serial: got hi
    - delay: 1s
    - write-serial: abcdef
    - wait-serial: rest def
    """
    path = project(tmp_path, "serial_echo", steps)
    (path.parent / "main.py").write_text(
        textwrap.dedent("""
        import select
        import sys
        print("ready")
        print("got", sys.stdin.readline().strip())
        p = select.poll()
        p.register(sys.stdin, select.POLLIN)
        while not p.poll(50):
            pass
        print("raw", sys.stdin.buffer.read(3))
        print("rest", sys.stdin.read())
        """)
    )
    outcome = run_scenario(path, out=tmp_path / "out")
    assert [r.end_us for r in outcome.results] == [1_000_000, 1_000_000, 1_001_000, 2_001_000, 2_001_000, 2_002_000]
    console = (tmp_path / "out" / "console.log").read_text()
    assert "[   1.001000] got hi" in console and "raw b'abc'" in console


def test_the_command_has_help():
    with pytest.raises(SystemExit) as done:
        main(["scenario", "--help"])
    assert done.value.code == 0


def test_make_hil_beside_a_rig_runs_its_scenario_files_too(tmp_path):
    from host.pytest_plugin.hil_run import tests_beside

    for name in ("rig.toml", "main.py", "test_mybot.py", "press.test.yaml", "notes.yaml"):
        (tmp_path / name).write_text("")
    assert [p.name for p in tests_beside(tmp_path / "rig.toml")] == ["press.test.yaml", "test_mybot.py"]
