"""One run's firmware coverage: the file the tracer writes, turned into coverage.py data.

The host opens a file for appending and passes its descriptor to the interpreter (the
``settrace`` variant, :func:`host.core.interpreter.find_variant`) as ``HIL_COVERAGE_FD``;
the shim's tracer (``host/shim/_hilcov.py``) appends one block per boot before it tells the
host the firmware ended. At the end of the run the blocks become a coverage.py data file
(``CoverageData`` with arcs, so line and branch coverage), each filename the firmware saw
(``main.py``, ``/lib/motor.py`` on the board's flash) mapped back to the source it was
flashed from, with the run's label as the coverage context. The firmware's other files are
marked measured with nothing run, so a module never imported shows as 0 %.
"""

import os
import tempfile
from pathlib import Path

from host.core import safefs
from host.core.errors import HarnessError
from host.rig.boardfs import board_name


class CoverageError(HarnessError):
    """The firmware's coverage could not be gathered or written."""


def sources(firmware) -> dict[str, Path]:
    """What the firmware may call a file -> the source it was flashed from: its board path
    (``main.py``, ``lib/motor.py``) and the host path itself (a run without a board copy)."""
    found: dict[str, Path] = {}
    for label, path in firmware.files():
        if path.suffix != ".py":
            continue
        found.setdefault(board_name(label), path.resolve())
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
        return write_data(self.data_file, arcs, sources(self.firmware), self.context)

    def abandon(self) -> None:
        """A run that never started: nothing to write."""
        try:
            os.close(self.fd)
        except OSError:
            pass
        Path(self._raw).unlink(missing_ok=True)


def write_data(data_file: Path, arcs: dict, known: dict[str, Path], context: str) -> Path:
    """coverage.py data (arcs, measured files) for the firmware's sources at ``data_file``."""
    by_source: dict[str, set] = {}
    for name, pairs in arcs.items():
        source = source_of(name, known)
        if source is not None:
            by_source.setdefault(str(source), set()).update(pairs)
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


def start(rig) -> None:
    """A rig that records coverage (``Recording.coverage``): its descriptor on the firmware."""
    if rig.coverage_file is not None and rig.coverage is None:
        label = f"{rig.app.name} seed {rig.seed}"
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
