"""``make conformance``: MicroPython's own tests on the plain unix port and in the loop,
with upstream's ``run-tests.py``; prints the table and checks it against ``known.toml``.

``python -m host.conformance [--table FILE]``. Exit status 1 when a test that passes on
the plain port fails in the loop and ``known.toml`` does not list it, or when
``known.toml`` lists a test that passes after all (the list is kept true). ``make test``
runs it whole (``host/tests/test_conformance.py``).

``--micropython VERSION`` runs another version's interpreter and that version's own tests
(its source tree's ``tests/``: docs/versions.md), with its results under
``build/conformance/<version>/``; a row of ``known.toml`` with ``versions = [...]`` holds for
those versions only (a row without it, for every version).
"""

import argparse
import contextlib
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import tomllib

from host.core import children, interpreter
from host.core.errors import SetupError
from host.core.paths import BUILD, REPO

HERE = Path(__file__).resolve().parent
OUT = BUILD / "conformance"
# The API the shim stands in for (machine, time, select, asyncio on them), by pattern.
TESTS = ("extmod/machine*.py", "extmod/ticks_*.py", "extmod/time_*.py", "extmod/select_*.py", "extmod/asyncio_*.py")
# Upstream's tests that need a board on a bench (loopback wires, a UART's TX to its RX):
# in the loop as an esp32 on the bench of host/conformance/inloop.py. The plain port
# has no such hardware; each must pass in the loop.
BENCH_TESTS = {  # file: the board it runs as (upstream's test names pins for it)
    "extmod/machine_uart_tx.py": "esp32",
    "extmod/machine_uart_irq_txidle.py": "rpi_pico",
    "extmod/machine_spi_rate.py": "esp32",
    "extmod_hardware/machine_uart_irq_rx.py": "esp32",
    "extmod_hardware/machine_uart_irq_rxidle.py": "esp32",
    "extmod_hardware/machine_uart_irq_break.py": "esp32",
}
STATUS = {"pass": "pass", "skip": "skip", "FAIL": "FAIL"}


def tests_dir() -> Path:
    path = interpreter.source_tree() / "tests"
    if not (path / "run-tests.py").is_file():
        raise SystemExit(f"error: no {path}/run-tests.py: run `make setup` (it fetches MicroPython's source)")
    return path


def select(tests: Path) -> tuple[list[str], list[str]]:
    """(the files to run, those left out because they need unittest: Debian's source
    (+ds) strips micropython-lib, where it lives, a tag's archive has it as an empty
    submodule, and run-tests.py stops on them)."""
    files = {p.relative_to(tests).as_posix() for pattern in TESTS for p in tests.glob(pattern)}
    needs = {f for f in files if "import unittest" in (tests / f).read_text()}
    return sorted(set(files) - needs), sorted(needs)


def wrapper() -> Path:
    """An executable run-tests.py can call as its MicroPython: the file in the loop."""
    OUT.mkdir(parents=True, exist_ok=True)
    path = OUT / "micropython-in-the-loop"
    path.write_text(
        "#!/bin/sh\n# run-tests.py's MicroPython: each test file in the loop (host/conformance/inloop.py)\n"
        f'PYTHONPATH="{REPO}" exec "{sys.executable}" -m host.conformance.inloop "$@"\n'
    )
    path.chmod(0o755)
    return path


def run_tests(tests: Path, files: list[str], micropython: Path, name: str, board: str = "") -> dict[str, str]:
    """Each file's result (pass, skip, FAIL) under ``micropython``, by run-tests.py."""
    from host.conformance.inloop import BOARD_ENV

    result_dir = OUT / name
    env = {**os.environ, "MICROPY_MICROPYTHON": str(micropython), "MICROPY_CPYTHON3": sys.executable, BOARD_ENV: board}
    cmd = [
        sys.executable,
        "run-tests.py",
        "--result-dir",
        str(result_dir),
        "-j",
        "1",
        *files,
    ]  # (one at a time: some bind port 8000)
    started = time.monotonic()
    proc = subprocess.run(
        cmd, cwd=tests, env=env, capture_output=True, text=True, timeout=1800, **children.popen_options()
    )
    (OUT / f"{name}.log").write_text(proc.stdout + proc.stderr)
    results = {}
    for line in proc.stdout.splitlines():
        m = re.match(r"^(pass|skip|FAIL)\s+(\S+)", line)
        if m:
            results[m.group(2)] = STATUS[m.group(1)]
    for f in files:
        results.setdefault(f, "error")  # run-tests stopped on it (a TestError)
    print(f"[conformance] {name}: {len(files)} files in {time.monotonic() - started:.1f} s (log: {OUT / name}.log)")
    return results


@contextlib.contextmanager
def fork_server():
    """The runs in the loop through one process that imported the harness once
    (:mod:`host.conformance.forkserver`), stopped and its socket removed after."""
    from host.conformance.inloop import SOCKET_ENV

    folder = tempfile.mkdtemp(prefix="mpy-fil-conformance-")
    path = os.path.join(folder, "server")
    env = {**os.environ, "PYTHONPATH": str(REPO), "OPENBLAS_NUM_THREADS": "1"}  # (no BLAS threads to fork)
    cmd = [sys.executable, "-m", f"{__package__}.forkserver", path]
    server = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, text=True, **children.popen_options())
    try:
        if server.stdout.readline().strip() != "ready":
            raise SystemExit(f"error: the conformance server did not start (exit {server.wait()}): {' '.join(cmd)}")
        os.environ[SOCKET_ENV] = path
        yield path
    finally:
        os.environ.pop(SOCKET_ENV, None)
        server.kill()
        server.wait()
        server.stdout.close()
        shutil.rmtree(folder, ignore_errors=True)


def known(version: str | None = None) -> dict[str, str]:
    """The listed tests' reasons that hold for ``version`` (the selected one by default): a
    row's ``versions``, when it has them, name the versions it holds for."""
    data = tomllib.loads((HERE / "known.toml").read_text())
    version = interpreter.release(version).version
    return {
        name: entry["reason"]
        for name, entry in data.get("test", {}).items()
        if version in entry.get("versions", interpreter.RELEASES)
    }


def bench_table(files, bench, reasons) -> str:
    lines = [
        "On the bench (loopback wires; the plain port has no such hardware):",
        "",
        "| test | as board | in the loop | note |",
        "|---|---|---|---|",
    ]
    lines += [
        f"| `{f}` | {BENCH_TESTS[f]} | {bench[f]} | {reasons.get(f, '') if bench[f] != 'pass' else ''} |" for f in files
    ]
    return "\n".join(lines) + "\n"


def table(files, plain, shim, reasons) -> str:
    lines = ["| test | plain unix port | in the loop | note |", "|---|---|---|---|"]
    for f in files:
        note = reasons.get(f, "")
        lines.append(f"| `{f}` | {plain[f]} | {shim[f]} | {note} |")
    counts = {k: sum(1 for f in files if shim[f] == k) for k in ("pass", "skip", "FAIL", "error")}
    plain_pass = sum(1 for f in files if plain[f] == "pass")
    lines.append("")
    lines.append(
        f"{len(files)} files: {plain_pass} pass on the plain port; in the loop {counts['pass']} pass, "
        f"{counts['skip']} skip, {counts['FAIL'] + counts['error']} fail."
    )
    return "\n".join(lines) + "\n"


def verdict(files, plain, shim, reasons, bench) -> list[str]:
    problems = [
        f"{f}: {status} on the bench (output: {OUT}/bench-{BENCH_TESTS[f]}/)"
        for f, status in bench.items()
        if status != "pass" and f not in reasons
    ]
    for f in files:
        if plain[f] == "pass" and shim[f] != "pass" and f not in reasons:
            problems.append(f"{f}: passes on the plain port, {shim[f]} in the loop (output: {OUT / 'shim'}/)")
        if f in reasons and shim[f] == "pass" and f not in bench:
            problems.append(f"{f}: listed in host/conformance/known.toml but passes in the loop: remove it")
    return problems


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(prog="python -m host.conformance", description=__doc__.splitlines()[0])
    ap.add_argument("--table", type=Path, help="also write the table (Markdown) to this file")
    ap.add_argument("--micropython", metavar="VERSION", help="this MicroPython version (docs/versions.md)")
    args = ap.parse_args(argv)
    global OUT
    if args.micropython:  # (the runs in the loop, run-tests.py's children, take it from the environment)
        version = interpreter.release(args.micropython).version
        os.environ[interpreter.VERSION_ENV] = version
        if version != interpreter.DEFAULT_VERSION:
            OUT = OUT / version
    try:
        print(f"[conformance] MicroPython {interpreter.release().version}: {interpreter.find()}")
    except SetupError as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    tests = tests_dir()
    files, needs_unittest = select(tests)
    plain = run_tests(tests, files, interpreter.find(), "plain")
    bench_files = [f for f in BENCH_TESTS if (tests / f).is_file()]
    bench = {}
    with fork_server():
        shim = run_tests(tests, files, wrapper(), "shim")
        for board in sorted({BENCH_TESTS[f] for f in bench_files}):
            group = [f for f in bench_files if BENCH_TESTS[f] == board]
            bench |= run_tests(tests, group, wrapper(), f"bench-{board}", board)
    reasons = known()
    text = table(files, plain, shim, reasons)
    if needs_unittest:
        left = ", ".join(needs_unittest)
        text += f"Not run (they need unittest, in micropython-lib, which the source leaves out): {left}.\n"
    if bench:
        text += "\n" + bench_table(bench_files, bench, reasons)
    print(text)
    if args.table:
        args.table.write_text(text)
    problems = verdict(files, plain, shim, reasons, bench)
    for p in problems:
        print("error:", p, file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
