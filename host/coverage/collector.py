"""One run's firmware coverage: the file the tracer writes, turned into coverage.py data.

The host opens a file for appending and passes its descriptor to the interpreter (the
``settrace`` variant, :func:`host.core.interpreter.find_variant`) as ``HIL_COVERAGE_FD``;
the shim's tracer (``host/shim/_hilcov.py``) appends one block per boot before it tells the
host the firmware ended. At the end of the run the blocks become a coverage.py data file
(``CoverageData`` with arcs, so line and branch coverage), each filename the firmware saw
(``main.py``, ``/lib/motor.py`` on the board's flash) mapped back to the source it was
flashed from, with the run's context: the test that ran it (its pytest node id, named by
the pytest plugin through :func:`name_context`), else the run's label. The firmware's other
files are marked measured with nothing run, so a module never imported shows as 0 %; a
test file beside the firmware (``test_*.py``, ``*_test.py``, ``conftest.py``: what pytest
collects) is not firmware and is not counted. Lines are marked as MicroPython runs them
(:mod:`.lines`: a ``while True:`` run through is run).
"""

import os
import tempfile
from pathlib import Path

from host.core import safefs
from host.core.errors import HarnessError


class CoverageError(HarnessError):
    """The firmware's coverage could not be gathered or written."""


_contexts: dict[str, str] = {}  # data file -> the context its run carries (the test's node id)


def name_context(data_file: Path, context: str) -> None:
    """The run that writes ``data_file`` carries ``context`` (the pytest plugin: the test)."""
    _contexts[str(Path(data_file))] = context


def context_of(data_file: Path, default: str) -> str:
    return _contexts.get(str(Path(data_file)), default)


def is_test_file(path: Path) -> bool:
    """A file pytest collects or reads (its default ``python_files`` and ``conftest.py``):
    the user's tests, not firmware."""
    name = Path(path).name
    return name == "conftest.py" or (name.startswith("test_") or name.endswith("_test.py")) and name.endswith(".py")


def sources(firmware) -> dict[str, Path]:
    """What the firmware may call a file -> the source it was flashed from: its board path
    (``main.py``, ``lib/motor.py``) and the host path itself (a run without a board copy);
    test files are not firmware."""
    found: dict[str, Path] = {}
    for on_board, path in firmware.board_files():  # (a Firmware of host/rig/targets: the rig hands it over)
        if path.suffix != ".py" or is_test_file(path):
            continue
        found.setdefault(on_board, path.resolve())
        found.setdefault(str(path), path.resolve())
        found.setdefault(str(path.resolve()), path.resolve())
    return found


def parse(text: str) -> dict[str, set[tuple[int, int]]]:
    """The tracer's blocks (``F name`` then ``A from,to ...``), every boot's merged."""
    arcs: dict[str, set[tuple[int, int]]] = {}
    name = None
    for line in text.splitlines():
        if line.startswith("F "):
            name = line[2:]
        elif line.startswith("A") and name is not None:
            pairs = (item.split(",") for item in line[1:].split())
            arcs.setdefault(name, set()).update((int(a), int(b)) for a, b in pairs)
            name = None
    return arcs


def source_of(name: str, known: dict[str, Path]) -> Path | None:
    """The source of a filename as the firmware saw it, or None (not the firmware's)."""
    if name in known:
        return known[name]
    bare = name.lstrip("/")
    while bare.startswith("./"):
        bare = bare[2:]
    return known.get(bare)


class RunCoverage:
    """One run's coverage: the descriptor its interpreter writes to, then its data file."""

    def __init__(self, firmware, data_file: Path, context: str):
        self.firmware = firmware
        self.data_file = Path(data_file)
        self.context = context
        handle, self._raw = tempfile.mkstemp(prefix="mpy-fil-coverage-")
        os.close(handle)
        self.fd = os.open(self._raw, os.O_WRONLY | os.O_APPEND)
        os.set_inheritable(self.fd, True)

    def finish(self) -> Path:
        """Close the descriptor and write the data file (a fresh one); the raw file goes."""
        try:
            os.close(self.fd)
            arcs = parse(Path(self._raw).read_text(errors="replace"))
        finally:
            Path(self._raw).unlink(missing_ok=True)
        return write_data(self.data_file, arcs, sources(self.firmware), self.context, _settrace_interpreter())

    def abandon(self) -> None:
        """A run that never started: nothing to write."""
        try:
            os.close(self.fd)
        except OSError:
            pass
        Path(self._raw).unlink(missing_ok=True)


def _settrace_interpreter() -> Path | None:
    from host.core import interpreter
    from host.core.errors import SetupError

    try:
        return interpreter.find_variant("settrace")
    except SetupError:
        return None


def write_data(
    data_file: Path, arcs: dict, known: dict[str, Path], context: str, micropython: Path | None = None
) -> Path:
    """coverage.py data (arcs, measured files) for the firmware's sources at ``data_file``;
    with ``micropython`` (the settrace variant) the arcs bridged over the lines it has no
    code for (:func:`host.coverage.lines.bridged`)."""
    by_source: dict[str, set] = {}
    for name, pairs in arcs.items():
        source = source_of(name, known)
        if source is not None:
            by_source.setdefault(str(source), set()).update(pairs)
    if micropython is not None:
        by_source = {source: as_micropython_runs(source, pairs, micropython) for source, pairs in by_source.items()}
    try:
        safefs.drop_links(safefs.make_folder(data_file.parent))  # (sqlite opens its files by name)
        data_file.unlink(missing_ok=True)
        from coverage import CoverageData  # (coverage.py only when there is coverage to write)

        data = CoverageData(basename=str(data_file))
        data.set_context(context)
        data.add_arcs(by_source)
        data.touch_files(sorted({str(p) for p in known.values()}))
        data.write()
    except OSError as e:
        raise CoverageError(f"cannot write the firmware's coverage to {data_file}: {e.strerror or e}") from e
    return data_file


def as_micropython_runs(source: str, pairs: set, micropython: Path) -> set:
    """The tracer's arcs of one source, bridged over its lines without bytecode."""
    from host.coverage import lines

    with_code = lines.micropython_lines(Path(source), micropython)
    possible = lines.cpython_arcs(Path(source)) if with_code is not None else None
    return lines.bridged(pairs, possible, with_code) if possible is not None else pairs


def start(rig) -> None:
    """A rig that records coverage (``Recording.coverage``): its descriptor on the firmware."""
    if rig.coverage_file is not None and rig.coverage is None:
        label = context_of(rig.coverage_file, f"{rig.app.name} seed {rig.seed}")
        rig.coverage = RunCoverage(rig.firmware, rig.coverage_file, label)
        rig.firmware.coverage_fd = rig.coverage.fd


def end(rig, write: bool = True) -> None:
    """The rig's run ended: its coverage written (``write``) or dropped."""
    run, rig.coverage = rig.coverage, None
    if run is None:
        return
    rig.firmware.coverage_fd = None
    if write:
        run.finish()
    else:
        run.abandon()
