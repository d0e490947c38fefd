"""A session's firmware coverage: every run's data file merged into one, its HTML and its
total (docs/coverage.md).

The runs' files (``.coverage.<test>.rig<n>``, each with its test's node id as coverage
context) and the merged ``.coverage`` sit in one folder, so ``coverage report`` and
``coverage html`` run there as in any Python project (``coverage combine`` reads the same
files); ``html/index.html`` shows the tests that ran each line (its contexts).
"""

import os
from pathlib import Path

import coverage
from coverage import CoverageData
from coverage.exceptions import CoverageException

from host.core import safefs
from host.coverage.collector import CoverageError

MERGED = ".coverage"


def run_files(folder: Path) -> list[Path]:
    """The runs' data files in ``folder`` (``.coverage.*``, not sqlite's own journals)."""
    return sorted(p for p in Path(folder).glob(MERGED + ".*") if p.is_file() and not p.name.endswith("-journal"))


def clear(folder: Path) -> None:
    """Remove an earlier session's data and HTML from ``folder`` (a session starts afresh)."""
    for path in [*run_files(folder), Path(folder) / MERGED]:
        path.unlink(missing_ok=True)


def merge(folder: Path, files: list[Path] | None = None) -> Path | None:
    """Merge the runs' data files into ``folder/.coverage``; None when there are none."""
    files = run_files(folder) if files is None else files
    if not files:
        return None
    out = Path(folder) / MERGED
    out.unlink(missing_ok=True)
    merged = CoverageData(basename=str(out))
    try:
        for path in files:
            run = CoverageData(basename=str(path))
            run.read()
            merged.update(run)
        merged.write()
    except (CoverageException, OSError) as e:
        raise CoverageError(f"cannot merge the firmware's coverage in {folder}: {e}") from e
    return out


def report(data_file: Path, html_dir: Path | None = None) -> float:
    """The total (lines and branches, %) of ``data_file``; its HTML in ``html_dir`` when given."""
    cov = coverage.Coverage(data_file=str(data_file), branch=True, config_file=False)
    try:
        cov.load()
        if html_dir is not None:
            return cov.html_report(directory=str(html_dir), show_contexts=True, title="Firmware coverage")
        with open("/dev/null", "w") as sink:
            return cov.report(file=sink)
    except (CoverageException, OSError) as e:
        raise CoverageError(f"cannot report the firmware's coverage of {data_file}: {e}") from e


def prepare_run(trace_folder: Path, version: str | None = None) -> Path:
    """``mpy-fil run --coverage``: the settrace variant of the run's MicroPython ``version``
    (its rig file's ``[interpreter] version``; None: the selected one) built if missing; the
    run's data file (``<trace folder>/coverage/.coverage``, an earlier one removed)."""
    from host.core import interpreter

    interpreter.build_variant("settrace", version=os.environ.get(interpreter.VERSION_ENV) or version)
    data_file = safefs.drop_links(safefs.make_folder(Path(trace_folder) / "coverage")) / MERGED
    data_file.unlink(missing_ok=True)
    return data_file


def run_summary(data_file: Path) -> str:
    """One run's coverage: its HTML beside its data, and the line that says where."""
    if not Path(data_file).is_file():
        return f"firmware coverage: none written ({data_file})"
    html = safefs.drop_links(safefs.make_folder(Path(data_file).parent / "html"))  # (coverage.py writes by name)
    total = report(data_file, html)
    return f"firmware coverage: {total:.0f}% of lines and branches: {html / 'index.html'} (data: {data_file})"
