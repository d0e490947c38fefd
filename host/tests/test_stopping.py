"""What a run leaves when it is stopped, runs out of disk or prints without end, and how
`replay` and `plot` read a damaged or partial trace folder back (docs/traces.md,
docs/reliability.md). Each case is done to a live `mpy-fil run` subprocess."""

import contextlib
import json
import os
import resource
import signal
import subprocess
import sys
import tempfile
import textwrap
import time
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from host.artefacts import integrity
from host.artefacts.folder import load_trace
from host.core.children import die_with_parent
from host.core.paths import REPO
from host.tests.conftest import run_cli

LONG_S = "3000"  # longer than any test waits: the run is stopped before its end


def _children(pid: int) -> set[int]:
    found = set()
    for task in Path(f"/proc/{pid}/task").glob("*"):
        with contextlib.suppress(OSError):
            found |= {int(p) for p in (task / "children").read_text().split()}
    return found


def _as_from_a_terminal() -> None:
    """The child dies with the test, and gets the stop signals as a command typed at a
    terminal does (a test session started in the background ignores SIGINT, and mpy-fil
    keeps a signal ignored that it was started ignoring, as nohup asks)."""
    die_with_parent()
    for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
        signal.signal(sig, signal.SIG_DFL)


class LiveRun:
    """`mpy-fil run` in a subprocess; on close it and the interpreter it started are ended
    by their ids, whatever state the test left them in."""

    def __init__(self, out: Path, *args: str, preexec=_as_from_a_terminal):
        command = [sys.executable, "-m", "host.cli", "run", *args, "--out", str(out), "--no-plots"]
        self.out = out
        self.proc = subprocess.Popen(
            command, cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, preexec_fn=preexec
        )
        self.children: set[int] = set()

    def wait_streaming(self, min_bytes: int = 100_000, timeout_s: float = 120) -> None:
        """Until the link log holds ``min_bytes`` (the run has run a while)."""
        deadline = time.monotonic() + timeout_s
        link = self.out / "trace.jsonl"
        while time.monotonic() < deadline and self.proc.poll() is None:
            self.children |= _children(self.proc.pid)
            if link.is_file() and link.stat().st_size >= min_bytes:
                return
            time.sleep(0.05)
        raise AssertionError(f"the run wrote no {min_bytes} bytes of {link} in {timeout_s} s: {self.proc.poll()}")

    def finish(self, timeout_s: float = 120) -> tuple[int, str, str]:
        out, err = self.proc.communicate(timeout=timeout_s)
        return self.proc.returncode, out, err

    def close(self) -> None:
        if self.proc.poll() is None:
            self.proc.kill()
        self.proc.communicate()
        for pid in self.children:
            with contextlib.suppress(ProcessLookupError):
                os.kill(pid, signal.SIGKILL)


@pytest.fixture
def live(tmp_path):
    runs = []

    def start(*args, **kwargs) -> LiveRun:
        runs.append(LiveRun(tmp_path / "run", *args, **kwargs))
        return runs[-1]

    yield start
    for run in runs:
        run.close()


def assert_every_file_whole_or_marked(folder: Path) -> dict:
    """Each file of the folder is in the header's digests and matches, or is named
    incomplete by it; no file half-written under a temporary name."""
    header = json.loads((folder / "header.json").read_text())
    assert header["digest"] == integrity.header_digest(header)
    for path in folder.iterdir():
        if path.name == "header.json" or path.is_dir():
            continue
        assert not path.name.endswith(integrity.PART), f"{path} left half-written"
        if path.name in header["incomplete"]:
            continue
        assert path.name in header["files"], f"{path.name} is neither whole nor marked"
        digest = header["files"][path.name]  # (None: budgets.json, whose wall-clock figures vary)
        assert digest is None or integrity.file_digest(path) == digest, f"{path.name} does not match its digest"
    return header


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT, signal.SIGHUP])
def test_a_run_stopped_by_a_signal_leaves_a_whole_folder_marked_partial_that_replays_to_its_cut(live, sig):
    run = live("--app", "rover", "--duration", LONG_S)
    run.wait_streaming()
    run.proc.send_signal(sig)
    code, out, err = run.finish()
    assert code == 128 + sig, err
    assert err.strip() == f"mpy-fil run: stopped by {sig.name}", err
    header = assert_every_file_whole_or_marked(run.out)
    assert header["partial"] and header["stop"]["signal"] == sig.name and header["incomplete"] == {}
    # (the cut: where the firmware was; the plant may have looked a little ahead of it)
    assert 0 < header["stop"]["t_us"] <= header["t_end_us"] < int(LONG_S) * 10**6, header["stop"]
    assert {"signals.csv", "truth.csv", "budgets.json", "trace.vcd", "console.log", "trace.jsonl"} <= set(
        header["files"]
    )
    code, out, err = run_cli("replay", str(run.out))
    assert code == 0 and err == "", (out, err)
    assert f"the recording is partial (stopped by {sig.name}" in out and "same outputs" in out, out


def test_after_sigkill_the_console_and_link_log_read_to_their_last_whole_line_and_the_folder_says_partial(live):
    run = live("--app", "rover", "--duration", LONG_S)
    run.wait_streaming(min_bytes=300_000)  # (the rover prints a line at each leg: some are in)
    run.proc.kill()
    run.finish()
    lines = (run.out / "trace.jsonl").read_bytes().split(b"\n")
    assert len(lines) > 1000
    for line in lines[:-1]:
        json.loads(line)  # every whole line is a whole record (the last may be cut)
    console = (run.out / "console.log").read_text().splitlines()
    assert console and all(line.startswith("[") for line in console), console
    for command in ("replay", "plot"):
        own = {"replay": "replay", "plot": "plots"}[command]  # (the one folder each may make in it)
        code, out, err = run_cli(command, str(run.out), "--out", str(run.out / own))
        assert code == 2 and len(err.splitlines()) == 1, (command, err)
        assert "no signals.csv; the folder is partial: the run did not end" in err, err


def _size_limited(limit_bytes: int):
    def preexec():
        _as_from_a_terminal()
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # (a write past the limit fails with EFBIG)
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit_bytes, limit_bytes))

    return preexec


def test_a_size_limited_disk_ends_the_run_with_one_line_naming_the_file_and_marks_what_is_incomplete(live):
    run = live("--app", "rover", "--duration", LONG_S, preexec=_size_limited(400_000))
    code, out, err = run.finish()
    assert code == 1, err
    assert err.splitlines() == [err.strip()], err  # one line, no traceback
    assert f"cannot write {run.out / 'trace.jsonl'}: File too large" in err, err
    header = assert_every_file_whole_or_marked(run.out)
    assert header["partial"] and header["stop"]["reason"] == "cannot write trace.jsonl: File too large"
    assert "trace.jsonl" in header["incomplete"]
    code, out, err = run_cli("replay", str(run.out))
    assert code in (0, 2) and len(err.splitlines()) <= 1, err


def _mount_tmpfs(where: Path, size: str) -> bool:
    where.mkdir()
    done = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(where)], capture_output=True)
    return done.returncode == 0


def test_a_full_tmpfs_ends_the_run_with_one_line_and_leaves_every_file_whole_or_marked(tmp_path):
    disk = tmp_path / "disk"
    if os.geteuid() != 0 or not _mount_tmpfs(disk, "1m"):
        pytest.skip("mounting a tmpfs needs root (the size-limited test covers the same case)")
    run = LiveRun(disk / "run", "--app", "rover", "--duration", LONG_S)
    try:
        code, out, err = run.finish()
        assert code == 1 and err.splitlines() == [err.strip()], err
        assert f"cannot write {disk / 'run'}" in err and "No space left on device" in err, err
        header = assert_every_file_whole_or_marked(disk / "run")
        assert header["partial"] and header["incomplete"]
    finally:
        run.close()
        subprocess.run(["umount", str(disk)], check=True)


CHATTY_RIG = """
name = "chatty"
[board]
console_baud = 0  # free printing: at 115 200 baud 2 s carry 23 kB, not the 2 MB this prints
[board.pins]
LED = 2
[plant]
body = "bench"
[wiring]
LED = "probe:led"
[trace]
console_max_bytes = 65536
"""

CHATTY = """
import time
line = "x" * 999
while True:
    print(line)
    time.sleep_ms(1)
"""


def test_a_firmware_printing_1kb_a_ms_is_capped_in_the_console_and_its_vcd_with_the_drop_counted(live, tmp_path):
    folder = tmp_path / "chatty"
    folder.mkdir()
    (folder / "main.py").write_text(textwrap.dedent(CHATTY))
    (folder / "rig.toml").write_text(textwrap.dedent(CHATTY_RIG))
    code, out, err = live(str(folder / "rig.toml"), "--duration", "2").finish()
    assert code == 0, err
    run = tmp_path / "run"
    console = (run / "console.log").read_bytes()
    assert len(console) < 65536 + 200
    last = console.splitlines()[-1].decode()
    header = json.loads((run / "header.json").read_text())
    counts = header["console"]
    assert counts["max_bytes"] == 65536 and counts["dropped_bytes"] > 1_500_000, counts
    assert f"[mpy-fil: {counts['dropped_bytes']} bytes in {counts['dropped_lines']} lines dropped past the cap]" in last
    assert f"{counts['dropped_bytes']} bytes in {counts['dropped_lines']} lines dropped" in out
    assert (run / "trace.vcd").stat().st_size < 300_000  # (2 MB printed: the VCD holds the capped file's lines)


# -- damaged trace folders ------------------------------------------------------------------

FILES = ("header.json", "signals.csv", "truth.csv", "budgets.json", "console.log", "trace.jsonl", "trace.vcd")
BAD_VALUES = (None, -1, 10**30, 1e30, float("nan"), float("inf"), "text", [], {}, True, -(2**63))
FIELDS = ("t_end_us", "seed", "truth_period_us", "signals", "app", "board", "initial", "footprint_half_width_m")


@pytest.fixture(scope="module")
def recorded(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("recorded") / "run"
    code, _out, err = run_cli("run", "--app", "rover", "--duration", "2", "--out", str(out), "--no-plots")
    assert code == 0, err
    return out


damage = st.one_of(
    st.tuples(st.just("missing"), st.sampled_from(FILES), st.just(0), st.just(0)),
    st.tuples(st.just("truncate"), st.sampled_from(FILES), st.floats(0, 1), st.just(0)),
    st.tuples(st.just("flip"), st.sampled_from(FILES), st.floats(0, 1), st.integers(1, 255)),
    st.tuples(st.just("not-utf8"), st.sampled_from(FILES), st.floats(0, 1), st.just(0)),
    st.tuples(
        st.sampled_from(("field", "field-resealed")), st.sampled_from(FIELDS), st.sampled_from(BAD_VALUES), st.just(0)
    ),
)


def _damage(folder: Path, how) -> None:
    kind, name, where, extra = how
    if kind.startswith("field"):
        header = json.loads((folder / "header.json").read_text())
        header[name] = where
        if kind == "field-resealed":
            header = integrity.seal(header)
        (folder / "header.json").write_text(json.dumps(header))
        return
    path = folder / name
    data = path.read_bytes()
    at = min(int(where * len(data)), max(len(data) - 1, 0))
    if kind == "missing":
        path.unlink()
    elif kind == "truncate":
        path.write_bytes(data[:at])
    elif kind == "flip":
        path.write_bytes(data[:at] + bytes([data[at] ^ extra]) + data[at + 1 :])
    else:
        path.write_bytes(data[:at] + b"\xff\xfe\xc0" + data[at:])


def _unseal(folder: Path) -> None:
    """As a folder written before headers held digests."""
    header = json.loads((folder / "header.json").read_text())
    (folder / "header.json").write_text(json.dumps({k: v for k, v in header.items() if k not in ("files", "digest")}))


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(how=damage, command=st.sampled_from(("replay", "plot")), sealed=st.booleans())
def test_a_damaged_trace_folder_is_refused_in_one_line_or_read_never_a_traceback_or_a_long_run(
    recorded, how, command, sealed
):
    import shutil

    with tempfile.TemporaryDirectory(prefix="mpy-fil-damaged-") as tmp:
        folder = Path(tmp) / "run"
        shutil.copytree(recorded, folder)
        if not sealed:
            _unseal(folder)
        _damage(folder, how)
        started = time.monotonic()
        code, out, err = run_cli(command, str(folder), "--out", str(Path(tmp) / "out"))
        # (without digests, or resealed, a changed value is told by what it does: a replay may differ;
        # a missing file never is)
        unsealed = not sealed or how[0] == "field-resealed"
        changed = unsealed and command == "replay" and how[0] != "missing"
        assert code in ((0, 1, 2) if changed else (0, 2)), (how, code, out, err)
        lines = [line for line in err.splitlines() if not line.startswith("usage: ")]  # (argparse's)
        assert len(lines) <= 1 and "Traceback" not in err, (how, err)
        assert time.monotonic() - started < 60, how
        if code == 2:
            assert "trace folder" in err or "trace " in err, err


def test_a_header_end_past_what_was_recorded_is_refused_by_name(recorded, tmp_path):
    import shutil

    folder = tmp_path / "run"
    shutil.copytree(recorded, folder)
    header = json.loads((folder / "header.json").read_text())
    (folder / "header.json").write_text(json.dumps(integrity.seal({**header, "t_end_us": 10**9})))
    code, out, err = run_cli("replay", str(folder))
    assert code == 2 and "header.json t_end_us 1000000000 is outside what was recorded" in err, err
    load_trace(recorded)  # (the recording itself reads back whole)


@pytest.mark.parametrize(
    ("value", "message"),
    [("100", "expected 4096 to 1099511627776 bytes, got 100"), ('"64M"', "expected an integer, got '64M'")],
)
def test_a_console_cap_out_of_bounds_is_named_at_check(tmp_path, value, message):
    (tmp_path / "main.py").write_text(textwrap.dedent(CHATTY))
    rig = CHATTY_RIG.replace("console_max_bytes = 65536", f"console_max_bytes = {value}")
    (tmp_path / "rig.toml").write_text(textwrap.dedent(rig))
    code, out, err = run_cli("check", str(tmp_path / "rig.toml"))
    assert code == 2 and f"[trace] console_max_bytes: {message}" in err, err


def test_a_cut_while_the_plant_looked_ahead_is_where_the_firmware_was():
    """A signal while the firmware runs from a STATE at 13.2 s, the plant looked ahead to
    13.22 s: the recording's cut is 13.2 s, where the firmware was, so a replay compares
    what came before it (its outputs at 13.2 s had not come), not up to the plant's 13.22 s
    (where the replay's own outputs at 13.2 s were taken for missing ones)."""
    from types import SimpleNamespace

    from host.rig.loop.rig import recording_end

    stopped = KeyboardInterrupt()
    stopped.signal_name = "SIGTERM"
    logs = SimpleNamespace(error=None)
    rig = SimpleNamespace(
        t_us=13_220_000,
        clock=SimpleNamespace(firmware_us=13_200_000),
        console_log=SimpleNamespace(error=None, summary={}),
        linklog=logs,
    )
    stop = recording_end(rig, stopped)["stop"]
    assert stop == {"reason": "stopped by SIGTERM", "signal": "SIGTERM", "t_us": 13_200_000}, stop
