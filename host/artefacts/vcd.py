"""Value Change Dump (IEEE 1364 §18) of a recorded run, for a wave viewer (GTKWave).

One ``$scope module`` per role (sensors, actuators, probes, pins, truth) under the
app's scope; a dotted signal name becomes nested scopes (``motor_l.pwm`` is
``actuators.motor_l.pwm``). Variables:

=========================  =====================  ========================================
recorded kind              VCD variable           value
=========================  =====================  ========================================
``level``                  ``wire 1``             0 / 1 (``x`` until the firmware drives it)
``u16``, ``duty``          ``integer 32``         ADC counts / duty_u16, as binary
``bytes``                  ``wire 8``             the last byte received or sent
 (its ``<name>_text``)     ``string``             the line being received or sent as text
ground truth               ``real 64``            SI units as the column names say
notes (``events`` scope)   ``string``             a console line, a budget miss
``text`` (``buses`` scope) ``string``             a bus transaction, decoded (``bus:i2c0``)
=========================  =====================  ========================================

Time is virtual: ``$timescale 1us``, ``#t`` is microseconds since the run started.
When a variable changes more than once at the same microsecond, the last value is
written. ``string`` variables are GTKWave's extension of the standard: a value cannot
hold white space, so text is written with C escapes (a space is ``\x20``), which
GTKWave reads back as the text.

:func:`write_gtkw` writes the GTKWave save file that goes with it: every signal shown,
grouped by role and then by part, each in the format that reads best (levels as bits,
counts and duties in decimal, a UART byte as its character).
"""

import bisect
import heapq
import io
import os
import re
import tempfile
from array import array

TIMESCALE = "1us"
_SCOPES = {"bus": "buses"}  # a role's scope when its plural is not role + "s"
_ID_FIRST, _ID_LAST = 33, 126  # printable ASCII, as identifier codes


def write_vcd(
    path,
    *,
    top: str,
    comment: str,
    signals: dict,
    initial: dict,
    events,
    truth,
    notes=(),
    columns=None,
    streamed: "StreamedChanges | None" = None,
) -> dict:
    """``signals``: name -> {"role", "kind"}; ``events``: (t_us, name, value) in time
    order; ``truth``: (t_us, {column: value}) in time order; ``notes``:
    (t_us, channel, text) in time order (iterated twice), each channel a string variable of
    the ``events`` scope. All three may be iterables that read from disk (``events`` is
    read once): nothing here holds them whole. ``columns``: the truth's columns, when
    known (else found in a first pass over ``truth``). ``streamed``: the changes already
    made while the run went (:class:`StreamedChanges`), used when they were made for these
    signals, initial values and columns (``events`` and ``truth`` are then not read).
    Returns each variable's (full name in the file, kind) by (group, name), for
    :func:`write_gtkw`."""
    if columns is None:
        columns = {k for _t, row in truth for k in row}
    columns = sorted(set(columns) - {"t_us"})
    channels = sorted({channel for _t, channel, _text in notes})
    ids, paths, declared = _declare_all(top, signals, columns, channels)
    with open(path, "w", encoding="ascii", errors="replace") as f:
        f.write(f"$version mpy-fil $end\n$comment {_clean(comment)} $end\n$timescale {TIMESCALE} $end\n")
        f.write(declared)
        if streamed is not None and streamed.fits(signals, initial, columns, ids):
            streamed.write_to(f, ids, notes)
            return paths
        # $dumpvars holds every variable's value at time 0, after the changes at time 0
        body = _Body(ids, signals, initial, columns, f.write)
        body.feed(events, truth, notes, _NEVER)
        body.close()
    return paths


def _declare_all(top: str, signals: dict, columns: list, channels: list) -> tuple[dict, dict, str]:
    """Each variable's identifier code and full name by (group, name), and the declarations'
    text: a scope a role (then a part), the truth's, the notes' (``events``: last, so the
    other variables' codes do not depend on the notes)."""
    ids: dict[tuple[str, str], str] = {}
    tree: dict = {}
    for name, info in signals.items():
        parts = [_SCOPES.get(info["role"], info["role"] + "s"), *name.split(":", 1)[-1].split(".")]
        _insert(tree, parts, ("sig", name, info["kind"]))
        if _SAME_AS.get(info["kind"], info["kind"]) == "bytes":
            _insert(tree, [*parts[:-1], parts[-1] + "_text"], ("text", name, "text"))
    for col in columns:
        _insert(tree, ["truth", col], ("truth", col, "real"))
    for channel in channels:
        _insert(tree, ["events", channel], ("note", channel, "text"))
    paths: dict[tuple[str, str], str] = {}
    text = io.StringIO()
    text.write(f"$scope module {_ident(top)} $end\n")
    _declare(text, tree, ids, paths, _ident(top))
    text.write("$upscope $end\n$enddefinitions $end\n")
    return ids, paths, text.getvalue()


def merge_vcd(path, parts: dict, *, top: str, comment: str) -> dict:
    """One VCD at ``path`` of several boards' (``parts``: a board's name -> the VCD
    :func:`write_vcd` wrote for it), each board a scope of its own under ``top``
    (``<top>.<board>.sensors...``), on the one virtual time: a set of boards'
    (docs/multi-board.md). Each board's identifier codes get a prefix of its own, so none
    clash; the changes are merged in time order, read a line at a time. Returns each
    board's variables as (full name in the file, kind), for :func:`write_set_gtkw`."""
    boards = list(parts.items())
    if len(boards) > _ID_LAST - _ID_FIRST + 1:
        raise ValueError(f"merge_vcd: at most {_ID_LAST - _ID_FIRST + 1} boards, got {len(boards)}")
    prefixes = [chr(_ID_FIRST + i) for i in range(len(boards))]
    files = [open(vcd, encoding="ascii", errors="replace") for _name, vcd in boards]  # noqa: SIM115
    try:
        with open(path, "w", encoding="ascii", errors="replace") as f:
            f.write(f"$version mpy-fil $end\n$comment {_clean(comment)} $end\n$timescale {TIMESCALE} $end\n")
            f.write(f"$scope module {_ident(top)} $end\n")
            declared = {}
            for (name, _vcd), prefix, lines in zip(boards, prefixes, files, strict=True):
                f.write(f"$scope module {_ident(name)} $end\n")
                declared[name] = []
                f.write("".join(_declarations(lines, prefix, f"{_ident(top)}.{_ident(name)}", declared[name])))
                f.write("$upscope $end\n")
            f.write("$upscope $end\n$enddefinitions $end\n")
            blocks = [_blocks(lines, prefix, i) for i, (prefix, lines) in enumerate(zip(prefixes, files, strict=True))]
            first = [next(b, None) for b in blocks]  # (each file's $dumpvars: one block of them all)
            f.write("#0\n$dumpvars\n" + "".join(line for block in first if block for line in block[2]) + "$end\n")
            t_written = 0
            for t, _i, changes in heapq.merge(*blocks):
                if t != t_written:
                    f.write(f"#{t}\n")
                    t_written = t
                f.write("".join(changes))
    finally:
        for lines in files:
            lines.close()
    return declared


_KIND_OF_VAR = {("wire", "1"): "level", ("integer", "32"): "u16", ("wire", "8"): "bytes", ("string", "1"): "text"}
"""A declared variable's kind, as :func:`write_vcd` declares each (reals: ``real``)."""


def _declarations(lines, prefix: str, scope: str, found: list) -> list[str]:
    """A VCD's declarations inside its top scope, each identifier code prefixed (the file
    read up to its ``$enddefinitions``); each variable's (full name under ``scope``, kind)
    appended to ``found``."""
    out, depth, names = [], 0, [scope]
    for line in lines:
        if line.startswith("$enddefinitions"):
            break
        if line.startswith("$scope"):
            depth += 1
            if depth == 1:
                continue
            names.append(line.split()[2])
        elif line.startswith("$upscope"):
            depth -= 1
            if depth == 0:
                continue
            names.pop()
        elif line.startswith("$var"):
            words = line.split()
            words[3] = prefix + words[3]
            line = " ".join(words) + "\n"
            found.append((".".join([*names, words[4]]), _KIND_OF_VAR.get((words[1], words[2]), words[1])))
        if depth >= 1:
            out.append(line)
    return out


def write_set_gtkw(path, vcd_path, declared: dict) -> None:
    """GTKWave's save file for a set of boards' VCD (:func:`merge_vcd`'s): a group a board,
    in it a group a role (sensors, actuators, ... as :func:`write_gtkw` groups them)."""
    from vcd.gtkw import GTKWSave  # (only when a set's VCD is written)

    with open(path, "w", encoding="utf-8") as f:
        save = GTKWSave(f)
        save.comment("mpy-fil: a set of boards; open with `gtkwave trace.gtkw` from this folder")
        save.dumpfile(str(vcd_path), abspath=False)
        save.timestart(0)
        save.sst_expanded(True)
        save.signals_width(300)
        for board, variables in declared.items():
            roles: dict[str, list] = {}
            for full, kind in variables:
                roles.setdefault(full.split(".")[2], []).append((full, kind))
            with save.group(board):
                for role in sorted(roles, key=_role_order):
                    with save.group(role):
                        for full, kind in roles[role]:
                            save.trace(full, datafmt=_GTKW_FORMATS.get(kind, "bin"))


def _blocks(lines, prefix: str, order: int):
    """(t, order, value lines) for each instant of a VCD's body, identifier codes prefixed;
    the first, its ``$dumpvars`` at time 0."""
    t, changes, started = 0, [], False
    for line in lines:
        if line.startswith("#"):
            if started:
                yield t, order, changes
            t, changes, started = int(line[1:]), [], True
        elif line.startswith("$"):  # ($dumpvars, $end)
            continue
        elif line[0] in "bBrRs":
            value, code = line.rstrip("\n").rsplit(" ", 1)
            changes.append(f"{value} {prefix}{code}\n")
        elif line.strip():
            changes.append(f"{line[0]}{prefix}{line[1:]}")
    if started:
        yield t, order, changes


TEXT_LINE_MAX = 120  # characters of a UART line kept as text


def _uart_text():
    """For each UART (a ``_text`` variable): at each chunk, the line being received,
    or the line just completed until the next one starts."""
    lines: dict[str, str] = {}

    def text_at(name, value):
        text = lines.get(name, "") + bytes.fromhex(value).decode("latin-1").replace("\r", "")
        done, _, partial = text.rpartition("\n")
        lines[name] = partial[-TEXT_LINE_MAX:]
        shown = partial or done.rpartition("\n")[2]
        return shown[-TEXT_LINE_MAX:]

    return text_at


def write_gtkw(path, vcd_path, paths: dict) -> None:
    """GTKWave's save file for ``vcd_path``: ``gtkwave trace.gtkw`` opens the trace with
    every variable shown, grouped by role (sensors, actuators, probes, pins, truth,
    events) and then by part. ``paths``: what :func:`write_vcd` returned."""
    groups: dict[str, dict[str, list]] = {}
    for full, kind in sorted(paths.values()):
        parts = full.split(".")
        part = parts[2] if len(parts) > 3 else ""
        groups.setdefault(parts[1], {}).setdefault(part, []).append((full, kind))
    from vcd.gtkw import GTKWSave  # (only when a trace folder is written)

    with open(path, "w", encoding="utf-8") as f:
        save = GTKWSave(f)
        save.comment("mpy-fil: open with `gtkwave trace.gtkw` from this folder")
        save.dumpfile(str(vcd_path), abspath=False)
        save.timestart(0)
        save.sst_expanded(True)
        save.signals_width(260)
        for role in sorted(groups, key=_role_order):
            with save.group(role):
                for part, members in groups[role].items():
                    if part:
                        save.begin_group(part)
                    for full, kind in members:
                        save.trace(full, datafmt=_GTKW_FORMATS.get(kind, "bin"))
                    if part:
                        save.end_group(part)


def _role_order(role: str) -> tuple:
    order = ["sensors", "actuators", "probes", "pins", "buses", "truth", "events"]
    return (order.index(role) if role in order else len(order), role)


_GTKW_FORMATS = {"real": "real", "text": "ascii", "bytes": "ascii", "u16": "dec", "duty": "dec"}


def _real(value, code: str) -> str:
    return f"r{float(value):.9g} {code}" if value is not None else f"r0 {code}"


_UNSET = object()
_CHUNK = 2048  # instants formatted before each write
_NEVER = float("inf")
_CACHED = 1024  # a variable's value lines kept, at most (then forgotten, and kept anew)


class _Body:
    """The changes after the declarations: the ``$dumpvars`` (every variable's value at time
    0, after the changes at time 0), then each instant's changes, a variable's last one at
    that instant. At an instant: the signals' changes in the order recorded, then each
    UART's text that changed then (its ``_text`` variable: the line being received or sent),
    then the ground truth's row, then the notes. A ground-truth value the variable already
    shows is not written again; every other change is, as a repeated console line is an
    event of its own. A truth value equal to the column's last one (same type, and not a
    float zero: -0.0 == 0.0 but reads otherwise) gives the same line, so it is not
    formatted again.

    One pass over each stream (events, truth and notes may read from disk), merged by time
    by hand; a signal's value lines are kept by value (``_CACHED`` at most a signal)."""

    def __init__(self, ids: dict, signals: dict, initial: dict, columns: list, write):
        self.write_text = write
        truth_codes = [(col, ids[("truth", col)]) for col in columns]
        self.state = {  # code -> the line it shows (the $dumpvars, then the truth's last)
            ids[("sig", name)]: _value(info["kind"], initial.get(name), ids[("sig", name)])
            for name, info in signals.items()
        }
        self.state.update({code: _value("real", None, code) for _col, code in truth_codes})
        self.state.update({code: _value("text", "", code) for key, code in ids.items() if key[0] in ("text", "note")})
        self.truth_codes = [(i, col, code) for i, (col, code) in enumerate(truth_codes)]
        self.signals = {
            name: (code, signals[name]["kind"], {}) for (group, name), code in ids.items() if group == "sig"
        }
        self.texts = {name: code for (group, name), code in ids.items() if group == "text"}
        self.notes = {channel: code for (group, channel), code in ids.items() if group == "note"}
        self.raw = [_UNSET] * len(truth_codes)  # each column's last value formatted
        self.uart = _uart_text()
        self.out: list[str] = []
        self.dumping = True  # the changes go to the $dumpvars (at or before time 0)
        self.t_now = None
        self.t_ev = None  # the last event's instant
        self.in_order = True  # every event came at or after the one before
        self.last = self.state  # where the changes of the instant t_now go

    def at(self, t: int) -> dict:
        """The changes of the instant ``t`` (the one after those gathered so far)."""
        if t == self.t_now:
            return self.last
        if self.dumping:
            if t <= 0:
                return self.last
            self._dump()
            self.dumping = False
        elif self.last:
            self._instant(f"#{self.t_now}\n" + "\n".join(self.last.values()) + "\n")
        self.last = {}
        self.t_now = t
        return self.last

    def _dump(self) -> None:
        """The changes leave the $dumpvars (an instant after 0 comes)."""
        self.write_text("#0\n$dumpvars\n" + "\n".join(self.state.values()) + "\n$end\n")

    def _instant(self, text: str) -> None:
        self.out.append(text)
        if len(self.out) >= _CHUNK:
            self._flush()

    def _flush(self) -> None:
        self.write_text("".join(self.out))
        self.out.clear()

    def close(self) -> None:
        """The last instant, and everything out."""
        if self.dumping:
            self._dump()
        elif self.last:
            self._instant(f"#{self.t_now}\n" + "\n".join(self.last.values()) + "\n")
            self.last = {}
        self._flush()

    def feed(self, events, truth, notes, limit) -> None:
        """The events, then the rows and notes before ``limit`` (every event before it
        comes here, none later)."""
        self._rows, self._notes = iter(truth), iter(notes)
        self._next_row()
        self._next_note()
        signals, texts, held = self.signals, self.texts, []
        t_ev, last = self.t_ev, self.last
        for t, name, v in events:
            if t != t_ev:
                if held:  # (the UARTs' texts, after the instant's changes)
                    self._texts(last, held)
                if t_ev is not None and t < t_ev:
                    self.in_order = False
                if self.t_row < t or self.t_note < t:
                    self._before(t)
                last = self.at(t)
                t_ev = t
            signal = signals.get(name)
            if signal is not None:
                code, kind, lines = signal
                if type(v) is int or type(v) is str:
                    line = lines.get(v)
                    if line is None:
                        if len(lines) >= _CACHED:
                            lines.clear()
                        line = lines[v] = _value(kind, v, code)
                else:
                    line = _value(kind, v, code)
                last[code] = line
            if v and name in texts:
                held.append((name, v))
        self.t_ev = t_ev
        self._texts(last, held)
        self._before(limit)

    def _texts(self, last: dict, held: list) -> None:
        for name, value in held:
            code = self.texts[name]
            last[code] = _value("text", self.uart(name, value), code)
        held.clear()

    def _before(self, t: int) -> None:
        """The truth's rows and the notes before ``t``: at each instant, the row, then the notes."""
        while self.t_row < t or self.t_note < t:
            if self.t_row <= self.t_note:
                self._row(self.at(self.t_row), self.row[1])
                self._next_row()
            else:
                _t, channel, text = self.note
                code = self.notes.get(channel)
                if code is not None:
                    self.at(self.t_note)[code] = _value("text", text, code)
                self._next_note()

    def _next_row(self) -> None:
        self.row = next(self._rows, None)
        self.t_row = _NEVER if self.row is None else self.row[0]

    def _next_note(self) -> None:
        self.note = next(self._notes, None)
        self.t_note = _NEVER if self.note is None else self.note[0]

    def _row(self, last: dict, row: dict) -> None:
        raw, shown, get = self.raw, self.state, row.get
        for i, col, code in self.truth_codes:
            v = get(col, _UNSET)
            if v is _UNSET:
                continue
            before = raw[i]
            if v == before and type(v) is type(before) and (v != 0 or type(v) is not float):
                continue
            raw[i] = v
            line = f"r{v:.9g} {code}" if type(v) is float else _real(v, code)  # (_real's, without its call)
            if shown.get(code) != line:
                last[code] = shown[code] = line


class StreamedChanges(_Body):
    """The VCD's changes made while the run goes, from what it can no longer rewind
    (:class:`host.artefacts.streaming.Streamed` feeds it), to a temporary file; the notes
    (the console's lines, the budgets' misses: known at the end) are merged in when the
    file is written (:meth:`write_to`), each at the end of its instant's changes, as
    :class:`_Body` would have put it. Made for the signals, initial values and truth
    columns it was given: :meth:`fits` says whether they are those of the end."""

    def __init__(self, signals: dict, initial: dict, columns: list):
        self.signals_given = {name: dict(info) for name, info in signals.items()}
        self.initial_given = dict(initial)
        self.columns_given = sorted(set(columns) - {"t_us"})
        self.ids, _paths, _text = _declare_all("top", signals, self.columns_given, [])
        self.file = tempfile.TemporaryFile(prefix="mpy-fil-vcd-")
        self.size = 0  # bytes in the file
        self.pending = 0  # characters of the instants not yet in it
        self.times = array("q")  # each instant written: its time ...
        self.offsets = array("q")  # ... and where its text starts in the file
        self.dumped: dict | None = None  # the $dumpvars, once an instant after 0 came
        super().__init__(self.ids, signals, initial, self.columns_given, self._write)

    def _write(self, text: str) -> None:
        data = text.encode("ascii", "replace")
        self.file.write(data)
        self.size += len(data)
        self.pending = 0

    def _dump(self) -> None:
        self.dumped = dict(self.state)

    def _instant(self, text: str) -> None:
        self.times.append(self.t_now)
        self.offsets.append(self.size + self.pending)  # (ASCII: a character a byte)
        self.pending += len(text)
        super()._instant(text)

    def fits(self, signals: dict, initial: dict, columns: list, ids: dict) -> bool:
        """Whether the changes were made for these signals, initial values, columns and
        identifier codes (the notes' aside), all in time order."""
        return (
            self.in_order
            and signals == self.signals_given
            and initial == self.initial_given
            and sorted(set(columns) - {"t_us"}) == self.columns_given
            and {key: code for key, code in ids.items() if key[0] != "note"} == self.ids
        )

    def write_to(self, f, ids: dict, notes) -> None:
        """The $dumpvars and the changes, the notes merged in (``ids``: the file's codes,
        the notes' among them: after every other variable's, which are the ones made here)."""
        self.close()
        self.file.flush()  # (read back by offset below)
        state = dict(self.state if self.dumped is None else self.dumped)
        state.update({code: _value("text", "", code) for key, code in ids.items() if key[0] == "note"})
        later: dict[int, dict] = {}  # instant -> the notes' lines at it (after 0)
        for t, channel, text in notes:
            code = ids.get(("note", channel))
            if code is not None:
                (state if t <= 0 else later.setdefault(t, {}))[code] = _value("text", text, code)
        f.write("#0\n$dumpvars\n" + "\n".join(state.values()) + "\n$end\n")
        done = 0  # bytes of the file written
        times, offsets = self.times, self.offsets
        for t, lines in later.items():
            i = bisect.bisect_left(times, t)
            start = offsets[i] if i < len(times) else self.size
            self._copy(f, done, start)
            added = "\n".join(lines.values()) + "\n"
            if i < len(times) and times[i] == t:  # (its instant's changes, then the notes)
                done = offsets[i + 1] if i + 1 < len(times) else self.size
                f.write(self._read(start, done) + added)
            else:
                f.write(f"#{t}\n" + added)
                done = start
        self._copy(f, done, self.size)
        self.discard()

    def _read(self, start: int, end: int) -> str:
        return os.pread(self.file.fileno(), end - start, start).decode("ascii")

    def _copy(self, f, start: int, end: int) -> None:
        while start < end:
            n = min(end - start, 1 << 20)
            f.write(self._read(start, start + n))
            start += n

    def discard(self) -> None:
        self.file.close()


def _insert(tree: dict, path: list[str], leaf) -> None:
    node = tree
    for part in path[:-1]:
        child = node.setdefault(_ident(part), {})
        if not isinstance(child, dict):  # a signal and a scope share a name
            child = node.setdefault(_ident(part) + "_", {})
        node = child
    name = _ident(path[-1])
    while name in node:
        name += "_"
    node[name] = leaf


def _declare(f, tree: dict, ids: dict, paths: dict, prefix: str) -> None:
    for name, node in tree.items():
        if isinstance(node, dict):
            f.write(f"$scope module {name} $end\n")
            _declare(f, node, ids, paths, f"{prefix}.{name}")
            f.write("$upscope $end\n")
            continue
        code = _code(len(ids))
        ids[(node[0], node[1])] = code
        paths[(node[0], node[1])] = (f"{prefix}.{name}", _SAME_AS.get(node[2], node[2]))
        f.write(f"$var {_var_type(node[2])} {code} {name} $end\n")


_SAME_AS = {"uart": "bytes", "pwm": "duty"}  # plant input kinds recorded as these


def _var_type(kind: str) -> str:
    kind = _SAME_AS.get(kind, kind)
    if kind == "text":
        return "string 1"
    if kind == "real":
        return "real 64"
    if kind in ("u16", "duty"):
        return "integer 32"
    if kind == "bytes":
        return "wire 8"
    return "wire 1"


def _value(kind: str, value, code: str) -> str:
    kind = _SAME_AS.get(kind, kind)
    if kind == "text":
        return f"s{_escape(value or '')} {code}"
    if kind == "real":
        return _real(value, code)
    if kind == "bytes":
        if not value:
            return f"bx {code}"
        return f"b{format(bytes.fromhex(value)[-1], 'b')} {code}"
    if value is None:
        return f"x{code}" if kind == "level" else f"bx {code}"
    if kind in ("u16", "duty"):
        return f"b{format(int(value) & 0xFFFFFFFF, 'b')} {code}"
    return f"{1 if int(value) else 0}{code}"


def _code(n: int) -> str:
    """Identifier codes: !, ", #, ... ~, then two characters, and so on."""
    span = _ID_LAST - _ID_FIRST + 1
    out = ""
    while True:
        out += chr(_ID_FIRST + n % span)
        n //= span
        if n == 0:
            return out
        n -= 1


def _ident(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9_]", "_", text) or "_"


def _escape(text: str) -> str:
    """A string value: C escapes for white space, backslashes and what is not printable."""
    if _PLAIN_TEXT.fullmatch(text):
        return text
    if max(text) <= "\xff":
        return text.translate(_ESCAPES)
    return "".join(c if "!" <= c <= "~" and c != "\\" else f"\\x{ord(c) & 0xFF:02x}" for c in text)


_PLAIN_TEXT = re.compile(r"[!-\[\]-~]*")  # (printable, no backslash: as it is)
_ESCAPES = {i: f"\\x{i:02x}" for i in range(256) if not (ord("!") <= i <= ord("~") and i != ord("\\"))}


def _clean(text: str) -> str:
    return text.replace("$end", "(end)").replace("\n", " ")
