"""``make hil``: the firmware-in-the-loop session, with its inputs checked before it starts.

Without RIG: this project's scenarios (``hil_tests``), the table and the report in the
project's ``build/hil/``. With ``RIG=path/to/rig.toml`` (or the folder holding it): only the
test files beside that rig file (its folder, not the folders below or above), the report, the
artefacts and pytest's cache under ``build/`` beside the rig file (a rig of this project,
``examples/pico_bot``: under the project's ``build/``, the report in ``build/hil/<folder>/``);
with no test there, the rig file itself runs as a test of its budgets, and how to write one
is printed.
``FIRMWARE=build/vboard/<board>/fs``: the scenarios of the app flashed there, from the
flashed files. ``COVERAGE=1``: the firmware's coverage too (``--hil-coverage``, docs/coverage.md).
A RIG or FIRMWARE that does not exist: one line, exit code 2, nothing run.
``--out DIR`` (not in the Makefile): the artefacts, the report and pytest's cache under DIR;
``-k EXPR``: only the tests pytest's ``-k`` selects (host/tests/test_flash.py runs the
FIRMWARE= path so, on a few scenarios, without touching the project's build/).
"""

import argparse
import os
import sys
from pathlib import Path

from host.core.paths import REPO, output_root
from host.pytest_plugin.userpath import firmware_file, how_to_write_a_test

TEST_FILES = ("test_*.py", "*_test.py", "*.test.yaml")  # (the last: Wokwi automation scenarios)


class UsageProblem(Exception):
    """Bad input: one line for stderr, exit code 2."""


def rig_file(rig: str) -> Path:
    """The rig file RIG names (a file, or a folder holding rig.toml)."""
    path = Path(rig).expanduser()
    if path.is_dir():
        if not (path / "rig.toml").is_file():
            raise UsageProblem(f"RIG={rig}: no rig.toml in that folder (give the rig file's path)")
        return (path / "rig.toml").resolve()
    if not path.is_file():
        raise UsageProblem(f"RIG={rig}: no such rig file or folder")
    return path.resolve()


def tests_beside(rig: Path) -> list[Path]:
    """The test files in the rig file's folder, without the firmware's own."""
    found = sorted({p for pattern in TEST_FILES for p in rig.parent.glob(pattern) if p.is_file()})
    return [p for p in found if p.suffix != ".py" or not firmware_file(p, rig.parent)]


def firmware_folder(firmware: str) -> Path:
    path = Path(firmware).expanduser()
    if not path.is_dir():
        raise UsageProblem(f"FIRMWARE={firmware}: no such folder (make flash writes build/vboard/<board>/fs)")
    if not (path.resolve().parent / "flashed.json").is_file():
        raise UsageProblem(f"FIRMWARE={firmware}: nothing was flashed there (no flashed.json beside it): make flash")
    return path.resolve()


def pytest_args(args) -> tuple[list[str], Path]:
    """pytest's arguments and the folder to run it in."""
    selected = getattr(args, "k", "")  # (--out and -k: not the Makefile's)
    common = ["-q", "-rs", "-n", str(args.workers), "--dist", "loadgroup", *(["-k", selected] if selected else [])]
    out = Path(args.out).resolve() if getattr(args, "out", "") else None
    if out is not None:
        common += ["--hil-out", str(out), "-o", f"cache_dir={out / '.pytest_cache'}"]
    if not args.rig:
        marks = "hil and not long" if args.long == "0" else "hil"
        report = (out or REPO / "build" / "hil") / "report.html"
        return [*common, "-m", marks, "--hil-table", "--hil-report", str(report), "hil_tests"], REPO
    rig = rig_file(args.rig)
    build = output_root(rig)  # (build/ at the root of the user's repository)
    report = build / "hil" / "report.html"
    if rig.is_relative_to(REPO):  # (one of ours, examples/pico_bot: the project's build/, its report apart)
        build = REPO / "build"
        report = build / "hil" / rig.parent.name / "report.html"
    tests = tests_beside(rig)
    if not tests:
        print(f"no test beside {rig}: running the rig's own budgets as a test", flush=True)
        print(how_to_write_a_test(rig), flush=True)
    where = [str(p.relative_to(rig.parent)) for p in tests] or [rig.name]
    if out is not None:
        build, report = out, out / "report.html"
    placed = ["--rootdir", str(rig.parent), "-o", f"cache_dir={build / '.pytest_cache'}"]
    marks = ["-m", "not long"] if args.long == "0" else []
    return [*common, *placed, *marks, "--hil-table", "--hil-report", str(report), *where], rig.parent


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="make hil", description=__doc__.split("\n")[0])
    parser.add_argument("--rig", default="", help="a rig file or its folder: the tests beside it")
    parser.add_argument("--firmware", default="", help="a flashed board folder (build/vboard/<board>/fs)")
    parser.add_argument("--long", default="1", help="0: leave out the tests marked long")
    parser.add_argument("--workers", default=str((os.cpu_count() or 1) + 1))
    parser.add_argument("--coverage", action="store_true", help="the firmware's coverage too (docs/coverage.md)")
    parser.add_argument("--out", default="", help="the artefacts, report and pytest's cache under this folder")
    parser.add_argument("-k", default="", metavar="EXPR", help="only the tests pytest -k EXPR selects")
    args = parser.parse_args(argv)
    try:
        if args.firmware:
            os.environ["HIL_FIRMWARE"] = str(firmware_folder(args.firmware))
        else:
            os.environ.pop("HIL_FIRMWARE", None)
        argv, folder = pytest_args(args)
        argv += ["--hil-coverage"] if args.coverage else []
    except UsageProblem as e:
        print(f"make hil: {e}", file=sys.stderr)
        return 2
    os.chdir(folder)
    sys.stdout.flush()
    # (pytest in a process of its own making: this one imported the harness, which pytest
    # would then not rewrite the asserts of; signals reach it as they reached make's recipe)
    os.execv(sys.executable, [sys.executable, "-m", "pytest", *argv])


if __name__ == "__main__":
    raise SystemExit(main())
