"""The trace folder's biggest files made while the run goes: ``signals.csv``'s and
``truth.csv``'s lines and the VCD's changes, from the records the run can no longer rewind
(those before the time the clock last committed: :meth:`Recorder.commit`), a few at a
time (:meth:`Streamed.work`). The rig asks for a turn once each STATE is on its way to the
firmware (the link log's ``idle``), so this work overlaps the firmware's own, as the link
log's does; and the recorder asks for everything up to a commit before it spills the
records to disk. At the end (:func:`host.artefacts.folder.write_trace_folder`) what is
left is made and the files are those the folder's writers would have made from the whole
recording, byte for byte; where the recording changed under what was made (a signal or a
truth column that came after records went to disk, events out of time order, real time's),
the writers make the file from the recording, as they do without this.

Everything goes to unnamed temporary files (gone once closed), so memory stays bounded."""

import bisect
import shutil
import tempfile

from host.artefacts.csvlines import SignalLines, TruthLines
from host.artefacts.vcd import StreamedChanges

EVENTS_A_TURN = 256  # events taken at most in a turn (the instant's last ones may add a few)
ROWS_A_TURN = 32  # truth rows, likewise
_NEVER = float("inf")


class Streamed:
    def __init__(self, recorder):
        self.recorder = recorder
        self.signals_file = self.truth_file = self.vcd = None
        self.usable = True  # the events came in time order, none rewound once made (else nothing here is used)
        self.made_to = -_NEVER  # the records before this time are made
        self.columns_ok = True  # truth.csv's lines were made with the truth's columns
        self.vcd_ok = True  # the VCD's changes were made for the signals and columns there are
        self._start()

    def _start(self) -> None:
        """Make everything from the first record (nothing has gone to disk yet)."""
        self.close()
        recorder = self.recorder
        self.events_done = self.rows_done = 0  # records made, those spilled included
        self.signals_file = tempfile.TemporaryFile(prefix="mpy-fil-signals-")
        self.truth_file = tempfile.TemporaryFile(prefix="mpy-fil-truth-")
        self.signal_lines = SignalLines()
        self.columns = recorder.truth_columns()
        self.truth_lines = TruthLines(self.columns)
        self._seen = {*self.columns, "t_us"}
        self._signals = len(recorder.signals)
        self.vcd = StreamedChanges(recorder.signals, recorder.initial, self.columns)

    def work(self, limit: float | None = None, bounded: bool = True) -> None:
        """Make the lines of the records before ``limit`` (None: the recorder's last commit),
        ``bounded``: no more than about EVENTS_A_TURN events and ROWS_A_TURN rows. A
        temporary file that cannot be written leaves the files to the writers."""
        if not self.usable:
            return
        try:
            self._work(limit, bounded)
        except OSError:
            self.usable = False

    def _work(self, limit: float | None, bounded: bool) -> None:
        recorder = self.recorder
        spilled = recorder.events_spilled or recorder.rows_spilled
        if len(recorder.signals) != self._signals:  # (a signal first driven now)
            if spilled:
                self.vcd_ok = False
                self._signals = len(recorder.signals)
            else:
                self._start()
        limit = recorder.committed_us if limit is None else limit
        for _ in range(2):
            events, rows = recorder._events, recorder._truth
            i0, j0 = self.events_done - recorder.events_spilled, self.rows_done - recorder.rows_spilled
            if bounded and i0 + EVENTS_A_TURN < len(events):
                limit = min(limit, events[i0 + EVENTS_A_TURN][0])
            if bounded and j0 + ROWS_A_TURN < len(rows):
                limit = min(limit, rows[j0 + ROWS_A_TURN][0])
            batch = events[i0 : _before(events, limit, i0)]
            batch_rows = rows[j0 : _before(rows, limit, j0)]
            if self.columns_ok and not all(row.keys() <= self._seen for _t, row in batch_rows):
                if not spilled:  # (a truth column that came now: every row made again)
                    self._start()
                    continue
                self.columns_ok = self.vcd_ok = False
            break
        if not batch and not batch_rows:
            return
        self.signals_file.write(self.signal_lines(batch).encode())
        if not self.signal_lines.in_order:
            self.usable = False
            return
        if self.columns_ok:
            self.truth_file.write(self.truth_lines(batch_rows).encode())
        if self.vcd_ok:
            self.vcd.feed(batch, batch_rows, (), limit)
        self.events_done += len(batch)
        self.rows_done += len(batch_rows)
        self.made_to = max(self.made_to, limit)

    def rewound(self, t_us: int) -> None:
        """The recording went back to ``t_us``: what was made after it is void (the clock
        never rewinds past its commit, so this is never so; if it were, the writers'
        own files)."""
        if t_us + 1 < self.made_to:
            self.usable = False

    def finish(self) -> None:
        """The recording ended: every record made."""
        self.work(_NEVER, bounded=False)

    def truth_fits(self, columns: list[str]) -> bool:
        """Whether truth.csv's lines were made with these columns (the truth's at the end)."""
        return self.usable and self.columns_ok and self.columns == list(columns)

    def changes(self) -> StreamedChanges | None:
        """The VCD's changes, where they may fit (:meth:`StreamedChanges.fits` has the last word)."""
        return self.vcd if self.usable and self.vcd_ok else None

    def copy(self, file, f) -> None:
        """A streamed file's bytes onto ``f`` (a file open for bytes)."""
        file.flush()
        file.seek(0)
        shutil.copyfileobj(file, f, 1 << 20)

    def close(self) -> None:
        for file in (self.signals_file, self.truth_file):
            if file is not None:
                file.close()
        if self.vcd is not None:
            self.vcd.discard()


def _before(records: list, limit: float, start: int) -> int:
    """Where the records from ``start`` on stop being before ``limit`` (in time order, as
    bisect finds it): looked for from the end first (a turn's limit is the last commit,
    after which come only the few records of the exchange going on), by bisection past a
    few records."""
    end = len(records)
    for _ in range(8):
        if end <= start or records[end - 1][0] < limit:
            return end
        end -= 1
    return bisect.bisect_left(records, limit, start, end, key=_time)


def _time(record) -> int:
    return record[0]
