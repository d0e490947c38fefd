"""Bad input is refused by name before anything runs: rig files and ``--param`` values
out of bounds, of the wrong type, with control characters, paths outside the firmware,
names that would become paths elsewhere, damaged bytes and deep nesting; ``mpy-fil
check`` says so in one line with exit 2, and whatever it accepts builds a plant that
runs. Property-based (hypothesis, derandomized) over our own rig files mutated, plus one
regression test per class of damage."""

import argparse
import contextlib
import functools
import io
import json
import math
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import tomllib
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from host import cli
from host.core.errors import ConfigError
from host.core.paths import FIRMWARE, REPO
from host.rig.config.rigfile import load_rig
from host.rig.scan.pinscan import firmware_sources
from host.rig.scan.starter import starter
from sim_plant import catalogue

SETTINGS = settings(
    max_examples=150,
    derandomize=True,
    database=None,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)
SOURCES = sorted(FIRMWARE.glob("apps/*/rig*.toml")) + [REPO / "examples" / "pico_bot" / "rig.toml"]
NASTY = [
    math.inf,
    -math.inf,
    math.nan,
    1e308,
    -1e308,
    2**63 - 1,
    -(2**63),
    0,
    -1,
    0.0,
    -0.5,
    True,
    False,
    "",
    "../../../etc/passwd",
    "/etc/passwd",
    "a\x00b",
    "line\nbreak",
    "x" * 300,
    "1K",
    "99999999M",
    [],
    {},
    [[[[[[[[[[1]]]]]]]]]],
    [math.inf, 1, 2, 3],
    [1, -1, -1, 1],
]


def toml_value(value) -> str:
    """A value as inline TOML (what tomllib reads back as the same value)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf") if math.isinf(value) else repr(value)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    return "{" + ", ".join(f"{json.dumps(k)} = {toml_value(v)}" for k, v in value.items()) + "}"


def toml_text(data: dict) -> str:
    return "".join(f"{json.dumps(k)} = {toml_value(v)}\n" for k, v in data.items())


EXTRAS = """
[interpreter]
heap_size = "192K"
ticks_wrap_s = 1

[[faults]]
kind = "bounce"
signal = "button.start"
start_s = 1
end_s = 2
bounce_ms = 2.0

[[faults]]
kind = "missed_edges"
signal = "enc_l.a"
rate = 0.01

[[faults]]
kind = "wheel_slip"
wheel = "left"
slip = 0.3

[[faults]]
kind = "brownout"
at_s = 5

[[faults]]
kind = "heap"
size = "128K"
"""


@pytest.fixture(scope="module")
def folders(tmp_path_factory):
    """Our rig files' folders copied (firmware and all), each with its rig file's data;
    and the example with every other table (interpreter, faults) as one more."""
    root = tmp_path_factory.mktemp("rigs")
    copies = []
    for i, source in enumerate(SOURCES):
        folder = root / f"{i}-{source.parent.name}"
        shutil.copytree(source.parent, folder, ignore=shutil.ignore_patterns("__pycache__", "test_*"))
        copies.append((folder, tomllib.loads(source.read_text())))
    copies.append((copies[-1][0], tomllib.loads(SOURCES[-1].read_text() + EXTRAS)))
    return copies


def leaves(value, path=()):
    """Every place in a parsed rig file: (path of keys and indexes)."""
    yield path
    if isinstance(value, dict):
        for key, item in value.items():
            yield from leaves(item, (*path, key))
    elif isinstance(value, list):
        for i, item in enumerate(value):
            yield from leaves(item, (*path, i))


def replaced(data, path, value):
    if not path:
        return value
    head, rest = path[0], path[1:]
    if isinstance(data, dict):
        return {**data, head: replaced(data[head], rest, value)}
    return [replaced(item, rest, value) if i == head else item for i, item in enumerate(data)]


def check(path: Path) -> tuple[int, str]:
    """``mpy-fil check PATH`` in this process: (exit code, stderr); an exception that
    escapes would be a traceback and fails the test."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = cli.main(["check", str(path)])
    return code, err.getvalue()


def assert_checked(path: Path) -> None:
    """Accepted, and then every world builds a plant that runs 0.2 s; or refused in one
    line naming the file, with exit 2."""
    code, err = check(path)
    if code == 0:
        app = load_rig(path)
        for world in app.worlds.values():
            plant = app.make_plant(**world)
            plant.reset(1)
            plant.advance_to(200_000)
        return
    assert code == 2, err
    assert err.count("\n") == 1 and str(path) in err and "Traceback" not in err, err


values = st.one_of(
    st.sampled_from(NASTY),
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(min_value=-(2**63), max_value=2**63 - 1),
    st.text(max_size=12),
    st.lists(st.floats(allow_nan=True), max_size=5),
)


@SETTINGS
@given(data=st.data(), value=values)
def test_a_rig_file_with_any_value_replaced_is_refused_by_name_or_runs(folders, data, value):
    folder, parsed = data.draw(st.sampled_from(folders))
    if data.draw(st.booleans()):  # a value replaced
        where = data.draw(st.sampled_from([p for p in leaves(parsed) if p]))
        mutant = replaced(parsed, where, value)
    else:  # an option of the body's set
        body = catalogue.bodies()[parsed["plant"]["body"]]
        name = data.draw(st.sampled_from([o.name for o in body.OPTIONS]))
        mutant = {**parsed, "plant": {**parsed["plant"], name: value}}
    path = folder / "mutant.toml"
    path.write_text(toml_text(mutant))
    assert_checked(path)


@SETTINGS
@given(data=st.data())
def test_a_rig_file_damaged_as_bytes_is_refused_by_name_or_runs(folders, data):
    folder, parsed = data.draw(st.sampled_from(folders))
    raw = toml_text(parsed).encode()
    cut = data.draw(st.integers(min_value=0, max_value=len(raw)))
    how = data.draw(st.sampled_from(["truncate", "byte", "nest", "nul"]))
    if how == "truncate":
        raw = raw[:cut]
    elif how == "byte":
        raw = raw[:cut] + bytes([data.draw(st.integers(0, 255))]) + raw[cut + 1 :]
    elif how == "nest":
        depth = data.draw(st.integers(1, 5000))
        raw += b"deep = " + b"[" * depth + b"]" * depth + b"\n"
    else:
        raw = raw[:cut] + b"\x00" + raw[cut:]
    path = folder / "mutant.toml"
    path.write_bytes(raw)
    assert_checked(path)


param_values = st.one_of(
    st.sampled_from(NASTY),
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(min_value=-(2**70), max_value=2**70),
    st.lists(st.one_of(st.floats(), st.integers(-(10**6), 10**6)), max_size=6),
    st.lists(st.lists(st.floats(-200, 200), min_size=2, max_size=5), max_size=3),
)


@functools.cache
def _pico_bot():
    return load_rig(REPO / "examples" / "pico_bot" / "rig.toml")


@functools.cache
def _declared() -> dict:
    """The pico_bot rig's own declarations, as ``--param`` names them: its body's options
    and ``<part name>.<option>`` of each of its parts -> the option's spec."""
    table = tomllib.loads((REPO / "examples" / "pico_bot" / "rig.toml").read_text())["plant"]
    declared = {o.name: o.spec for o in catalogue.bodies()[table["body"]].OPTIONS}
    for part in table.get("parts", []):
        declared |= {f"{part['name']}.{o.name}": o.spec for o in catalogue.parts()[part["kind"]].OPTIONS}
    return declared


@SETTINGS
@given(name=st.sampled_from(sorted(_declared())), value=param_values)
def test_a_param_is_checked_against_the_rigs_own_declaration_and_then_runs(tmp_path, name, value):
    """``--param NAME=VALUE``: refused (at argument time when not finite, else when the
    plant is built, naming the option) exactly when the rig's declaration of the option
    refuses the value; a value it takes builds a plant that runs (or is refused by the
    part's own cross-checks, naming it)."""
    text = f"{name}={value!r}"
    try:
        _, parsed = cli._param(text)
    except argparse.ArgumentTypeError as e:
        assert str(e).startswith(f"{name}: ") and "\n" not in str(e) and not _finite(value), e
        return
    spec = _declared()[name]
    problem = None if parsed is None else spec.problem(parsed)
    try:
        plant = _pico_bot().make_plant(**{name: parsed})
    except (TypeError, ValueError, ArithmeticError, ConfigError) as e:
        option = name.rpartition(".")[2]
        assert f" {option}" in str(e) and "\n" not in str(e), f"{text}: the refusal names no option: {e}"
        if problem is not None:
            assert problem in str(e), f"{text}: expected the declaration's {problem!r}, got {e}"
        return
    assert problem is None, f"{text}: the declaration refuses it ({problem}) but the plant was built"
    plant.reset(1)
    plant.advance_to(200_000)


def _finite(value) -> bool:
    return cli._finite(value)


# -- one regression test per class of bad input ------------------------------------------


GOOD = (REPO / "examples" / "pico_bot" / "rig.toml").read_text()


@pytest.fixture
def pico(tmp_path):
    folder = tmp_path / "pico_bot"
    folder.mkdir()
    shutil.copy(REPO / "examples" / "pico_bot" / "main.py", folder)
    return folder


def refused(folder: Path, text: str | bytes, field: str, says: str) -> str:
    path = folder / "rig.toml"
    path.write_bytes(text if isinstance(text, bytes) else text.encode())
    code, err = check(path)
    assert code == 2 and err.count("\n") == 1, err
    assert f"{path}: {field}" in err and says in err, err
    with pytest.raises(ConfigError):
        load_rig(path)
    return err


@pytest.mark.parametrize(
    ("old", "new", "field", "says"),
    [
        # sizes: infinite, huge, zero, negative, true/false
        ("room_w_m = 3.0", "room_w_m = inf", "[plant] room_w_m", "from 0.1 to 100, got inf"),
        ("room_w_m = 3.0", "room_w_m = 1e308", "[plant] room_w_m", "got 1e+308"),
        ("room_w_m = 3.0", "room_w_m = true", "[plant] room_w_m", "got True"),
        ("room_w_m = 3.0", "room_w_m = nan", "[plant] room_w_m", "got nan"),
        ("room_w_m = 3.0", "wheel_radius_m = 0", "[plant] wheel_radius_m", "from 0.001 to 1, got 0"),
        ("[[1.6, 1.0, 0.3, 0.3]]", "[[1.6, 1.0, -0.3, 0.3]]", "[plant] obstacles", "item 2"),
        ("lines_per_rev = 7", "lines_per_rev = 1000000000", "[[plant.parts]] #4 (enc_l) lines_per_rev", "1 to 10000"),
        ("lines_per_rev = 7", "lines_per_rev = 7.5", "[[plant.parts]] #4 (enc_l) lines_per_rev", "a whole number"),
        ("time_constant_ms = 0 ", "time_constant_ms = -1 ", "[[plant.parts]] #1 (motor_l) time_constant_ms", "0 to"),
        ('bridge = "tb6612"', 'bridge = "tb6612"\npolarity = 0', "[[plant.parts]] #1 (motor_l) polarity", "-1, 1"),
        ('name = "start"', 'name = "st\\u0000art"', "plant.parts[7].name", "control character"),
        ("room_w_m = 3.0", 'world = "../room"', "[plant] world", "expected one of room"),
        # worlds: the same bounds; names that become a folder's name
        ("[worlds.open-room]", "[worlds.open-room]\nroom_h_m = -2", "[worlds.open-room]: [plant] room_h_m", "got -2"),
        ("[worlds.open-room]", '[worlds."../../x"]', "[worlds.../../x]", "expected a name"),
        ('name = "pico_bot"', 'name = "../../../tmp/x"', "name", "expected a name"),
        ('name = "pico_bot"', 'name = "a\\u0000b"', "name", "control character"),
        # pins
        ("LED = 25", "LED = -1", "[board.pins] LED", "from 0 to 255, got -1"),
        ("LED = 25", "LED = 9223372036854775807", "[board.pins] LED", "from 0 to 255"),
        ("LED = 25", 'LED = "GP/25"', "[board.pins] LED", "expected a pin name"),
        # budgets: times and the marker
        ("period_us = 50_000", "period_us = 9223372036854775807", "[budgets.loop] period_us", "1 to 3600000000"),
        ("tolerance_us = 2_000", "tolerance_us = -1", "[budgets.loop] tolerance_us", "0 to 3600000000"),
        ('kind = "period"', 'kind = "period"\nmarker = "$$"', "[budgets.loop] marker", "one character"),
        ('kind = "period"', 'kind = "period"\nmarker = "\\u00e9"', "[budgets.loop] marker", "one byte"),
        # paths outside the firmware
        ('entry = "main.py"', 'entry = "/etc/passwd"', "[firmware] entry", "outside the firmware folder"),
        ('entry = "main.py"', 'entry = "../../../../etc/passwd"', "[firmware] entry", "outside"),
        ('entry = "main.py"', 'entry = "main.py"\ndir = "/usr/lib/python3"', "[firmware] dir", "outside"),
        ('entry = "main.py"', 'entry = "main.py"\nlib = ["/usr/lib"]', "[firmware] lib", "outside"),
        # heap_size: what -X heapsize reads, bounded
        ('entry = "main.py"', 'entry = "main.py"\n[interpreter]\nheap_size = "1K"', "[interpreter] heap_size", "1K"),
        (
            'entry = "main.py"',
            'entry = "main.py"\n[interpreter]\nheap_size = "99999M"',
            "[interpreter] heap_size",
            "more than a board has",
        ),
        (
            'entry = "main.py"',
            'entry = "main.py"\n[interpreter]\nheap_size = "010K"',
            "[interpreter] heap_size",
            "010K",
        ),
        (
            'entry = "main.py"',
            'entry = "main.py"\n[interpreter]\nheap_size = "1.5M"',
            "[interpreter] heap_size",
            "1.5M",
        ),
        (
            'entry = "main.py"',
            'entry = "main.py"\n[interpreter]\nheap_size = true',
            "[interpreter] heap_size",
            "expected",
        ),
    ],
)
def test_each_class_of_bad_value_is_refused_by_name(pico, old, new, field, says):
    assert old in GOOD
    refused(pico, GOOD.replace(old, new, 1), field, says)


def test_damaged_bytes_and_deep_nesting_are_refused_by_name(pico):
    refused(pico, GOOD.encode().replace(b"pico_bot", b"pico_\xffbot", 1), "not UTF-8 text", "byte")
    refused(pico, GOOD + "deep = " + "[" * 5000 + "]" * 5000 + "\n", "not valid TOML", "nested deeper")
    refused(pico, GOOD + "deep = " + "[" * 20 + "]" * 20 + "\n", "worlds.open-room.deep", "nested deeper than 8")
    refused(pico, GOOD + "# " + "x" * (1 << 20) + "\n", "expected a rig file of at most", "bytes")


def test_a_board_file_outside_the_rig_files_folder_is_refused(pico):
    (pico.parent / "board.py").write_text("LED = const(25)\n")
    text = GOOD.split("[board.pins]")[0] + '[board]\nfile = "../board.py"\n\n[plant]' + GOOD.split("[plant]")[1]
    refused(pico, text, "[board] file", "outside the rig file's folder")


def test_a_symlink_out_of_the_firmware_is_outside_it(pico):
    (pico / "main2.py").symlink_to("/etc/hostname")
    refused(pico, GOOD.replace('entry = "main.py"', 'entry = "main2.py"'), "[firmware] entry", "outside")


@pytest.mark.parametrize(
    ("size", "ok"),
    [
        ("24K", True),
        ("23K", False),
        ("192k", True),
        ("2M", True),
        ("0x30000", True),
        ("64wK", True),
        (262144, True),
        ("1G", False),
    ],
)
def test_heap_size_takes_what_the_unix_port_reads(pico, size, ok):
    value = json.dumps(size) if isinstance(size, str) else str(size)
    path = pico / "rig.toml"
    path.write_text(GOOD.replace('entry = "main.py"', f'entry = "main.py"\n[interpreter]\nheap_size = {value}'))
    if ok:
        assert load_rig(path).interpreter.heap_size == str(size)
    else:
        with pytest.raises(ConfigError, match=r"\[interpreter\] heap_size: expected bytes from 24K to 1024M"):
            load_rig(path)


def test_the_smallest_heap_a_rig_file_takes_still_starts_the_firmware(make_rig, pico):
    """The lower bound is real: with 24K of its own the firmware starts and runs (the shim's heap is on top)."""
    (pico / "main.py").write_text("print('started')\n")
    path = pico / "rig.toml"
    path.write_text(GOOD.replace('entry = "main.py"', 'entry = "main.py"\n[interpreter]\nheap_size = "24K"'))
    rig = make_rig(str(path), allow_exit=True)
    rig.run_for(0.1)
    rig.stop()
    assert "started" in rig.console, rig.console


@pytest.mark.parametrize(
    ("param", "says"),
    [
        ("room_w_m=inf", "argument --param: room_w_m: expected finite numbers"),
        ("room_w_m=1e308", "[plant] room_w_m: expected a number of metres from 0.1 to 100"),
        ("room_w_m=True", "[plant] room_w_m: expected a number of metres"),
        ("wheel_radius_m=-1", "[plant] wheel_radius_m: expected a number of metres from 0.001 to 1, got -1"),
        ("enc_l.lines_per_rev=1e9", "(enc_l) lines_per_rev: expected a whole number from 1 to 10000"),
        ("obstacles=[[1, 1, -1, 1]]", "[plant] obstacles: [0]: [cx_m, cy_m, w_m, h_m], item 2"),
        ("world='../x'", "[plant] world: expected one of room"),
        ("slip_period_us=500", "[plant] slip_period_us: expected a whole number of microseconds from 1000"),
        ("lines_per_rev=20", "[plant] lines_per_rev: the differential has no such option"),
    ],
)
def test_mpy_fil_run_refuses_a_param_as_the_rigs_own_declaration_does(param, says, capsys):
    """The rover's rig declares its options (its body's and each part's): ``--param`` is
    checked against them before anything runs (exit 2, one line, the option named)."""
    with pytest.raises(SystemExit) as stop:
        cli.main(["run", "--param", param])
    err = capsys.readouterr().err
    assert stop.value.code == 2, err
    last = err.splitlines()[-1]
    assert last.startswith("mpy-fil run: error: argument --param: ") and says in last, last


def test_the_cli_refuses_bad_input_in_one_line_without_a_traceback(pico):
    """The real front end, once for a rig file and once for a --param."""
    path = pico / "rig.toml"
    path.write_text(GOOD.replace("room_w_m = 3.0", "wheel_radius_m = 0"))
    done = subprocess.run(
        [sys.executable, "-m", "host.cli", "check", str(path)], capture_output=True, text=True, cwd=REPO, timeout=60
    )
    assert done.returncode == 2 and done.stderr.count("\n") == 1, done.stderr
    assert "[plant] wheel_radius_m" in done.stderr and "Traceback" not in done.stderr
    done = subprocess.run(
        [sys.executable, "-m", "host.cli", "run", "--param", "wheel_radius_m=-1"],
        capture_output=True,
        text=True,
        cwd=REPO,
        timeout=60,
    )
    assert done.returncode == 2 and "Traceback" not in done.stderr
    assert done.stderr.splitlines()[-1].endswith(
        "argument --param: rover's plant rejects it: [plant] wheel_radius_m: expected a number of metres "
        "from 0.001 to 1, got -1"
    )


def test_every_option_of_every_part_and_body_has_bounds_and_its_default_is_within_them():
    for kind, cls in {**catalogue.parts(), **catalogue.bodies()}.items():
        for opt in cls.OPTIONS:
            assert hasattr(opt.spec, "problem"), f"{kind}.{opt.name}: no bounds ({opt.spec!r})"
            assert opt.default is None or opt.spec.problem(opt.default) is None, (kind, opt.name, opt.default)


# -- init ----------------------------------------------------------------------------------


def test_init_skips_hidden_folders_and_virtual_environments(tmp_path):
    (tmp_path / "main.py").write_text("from machine import Pin\nLED = Pin(25, Pin.OUT)\n")
    for folder in (".venv/lib", "env/lib/python3.12/site-packages/x", "node_modules/y", "__pycache__", "build", ".git"):
        (tmp_path / folder).mkdir(parents=True)
        (tmp_path / folder / "mod.py").write_text("from machine import Pin\nPin(99)\n")
    (tmp_path / "env" / "pyvenv.cfg").write_text("home = /usr/bin\n")
    (tmp_path / "lib").mkdir()
    (tmp_path / "lib" / "drv.py").write_text("from machine import Pin\nPin(7)\n")
    assert firmware_sources(tmp_path) == [tmp_path / "main.py", tmp_path / "lib" / "drv.py"]
    text = starter(tmp_path).replace(str(tmp_path), "<folder>")  # (pytest's folder may hold a 99)
    assert "PIN_7 = 7" in text and "99" not in text


def test_init_stops_at_its_bounds_and_says_so(tmp_path, monkeypatch):
    from host.rig.scan import pinscan

    monkeypatch.setattr(pinscan, "SCAN_MAX_FILES", 5)
    for i in range(20):
        (tmp_path / f"m{i:02}.py").write_text(f"from machine import Pin\nPin({i})\n")
    notes: list[str] = []
    text = starter(tmp_path, notes)
    assert len(notes) == 1 and "stopped reading at" in notes[0] and "after 5 files" in notes[0], notes
    assert "PIN_4 = 4" in text and "PIN_5 =" not in text
    code = subprocess.run(
        [sys.executable, "-c", "import host.rig.scan.pinscan as r; r.SCAN_MAX_BYTES = 40; from host import cli; "
         f"raise SystemExit(cli.main(['init', {str(tmp_path)!r}]))"],
        capture_output=True, text=True, cwd=REPO, timeout=60,
    )  # fmt: skip
    assert code.returncode == 0 and "mpy-fil init: stopped reading at" in code.stderr, code.stderr


@SETTINGS
@given(
    arg=st.one_of(
        st.text(max_size=40),
        st.text(min_size=300, max_size=5000, alphabet="ab/."),
        st.sampled_from(["/etc/passwd", "/dev/zero", "/proc/self", "..", ".", "a\x01.toml", "x.toml"]),
    )
)
def test_check_and_init_name_any_bad_argument_in_one_line(arg):
    """Whatever the RIG or DIR argument (a name too long, a control character, a
    device): exit 2 with one line (after argparse's usage), never a traceback."""
    err = io.StringIO()
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
        code = cli.main(["check", arg])
    assert code in (0, 2) and (code == 0 or err.getvalue().count("\n") == 1), err.getvalue()
    if _is_folder(arg):
        return  # (init would write a rig.toml there)
    err = io.StringIO()
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err), pytest.raises(SystemExit) as done:
        cli.main(["init", arg])
    assert done.value.code == 2 and "Traceback" not in err.getvalue()
    assert err.getvalue().splitlines()[-1].startswith("mpy-fil init: error: argument DIR"), err.getvalue()


def _is_folder(arg: str) -> bool:
    try:
        return Path(arg).is_dir()
    except (OSError, ValueError):
        return False
