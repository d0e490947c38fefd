"""The link log (``trace.jsonl``): what crossed the link, decoded, one JSON object per
line, in virtual time.

It holds the link messages and what the plant reported, never wall-clock figures, so
the same (app, board, plant, seed, commit) gives the same bytes. The firmware's console
goes to its own file, since its pipe is not ordered with the link. ``digest`` is a
SHA-256 of the lines, kept even when no file is written. A rig that does not trace logs
to :data:`NO_LOG`, which keeps nothing.

The records of an exchange are kept as they come (their numbers, not yet text) and written
together when its STATE is logged, which the clock does once the STATE is on its way: the
formatting, hashing and one write then overlap the firmware's own work on it. Each write
ends at a whole line and reaches the file at once (one unbuffered write), so a run killed outright
(SIGKILL) leaves every record up to the last STATE sent, to its last whole line; a stopped
run's (``close``) and the digest hold every record. A write that fails (a full disk)
raises :class:`~host.artefacts.integrity.TraceWriteError` once; the file stays as it was
cut (:attr:`LinkLog.error`) and later records are only hashed.
"""

import contextlib
import hashlib
import json
from pathlib import Path

from host.artefacts.integrity import TraceWriteError
from host.core import safefs
from host.link import frames as F

KEPT_MAX = 512  # records kept unwritten at most (a run with no STATE to write them at)

OUT_ATTRS = {F.OUT_LEVEL: "level", F.OUT_DUTY: "duty_u16", F.OUT_FREQ: "freq", F.OUT_DEINIT: "deinit"}


class LinkLog:
    def __init__(self, path: Path | None = None):
        self.path = path
        # (unbuffered bytes: each flush one write of whole lines, the bytes hashed)
        self._file = safefs.open_write(path, "wb", buffering=0) if path else None  # (no link)
        self._hash = hashlib.sha256()
        self._written = 0  # lines hashed (and written)
        self._pending: list[tuple] = []  # (format, args) of each record not yet written
        self.error: TraceWriteError | None = None
        self.idle = None  # called once each STATE is logged: work that may overlap the firmware's

    _encode = json.JSONEncoder(separators=(",", ":"), sort_keys=True).encode  # (json.dumps makes one per call)

    def write(self, record: dict) -> None:
        self._pending.append((_as_is, (self._encode(record) + "\n",)))
        if len(self._pending) >= KEPT_MAX:
            self.flush()

    def line(self, line: str) -> None:
        """One record already in JSON, written now with those before it."""
        self._pending.append((_as_is, (line,)))
        self.flush()

    def flush(self) -> None:
        """Write (and hash) the records kept so far, in one write."""
        pending, self._pending = self._pending, []
        if pending:
            self._put("".join([form(*args) for form, args in pending]), len(pending))

    def _put(self, text: str, lines: int) -> None:
        data = text.encode()
        self._hash.update(data)
        self._written += lines
        if self._file:
            try:
                done = self._file.write(data)
                while done < len(data):  # (a write cut short: the rest, or the error that cut it)
                    done += self._file.write(memoryview(data)[done:])
            except OSError as e:
                self._fail(e)

    def _fail(self, e: OSError) -> None:
        file, self._file = self._file, None
        try:
            file.close()
        except OSError:
            pass  # (what could not be flushed is lost: the error says where)
        self.error = TraceWriteError(self.path, e)
        raise self.error from e

    @property
    def lines(self) -> int:
        """Records logged so far."""
        return self._written + len(self._pending)

    @property
    def digest(self) -> str:
        self.flush()
        return self._hash.hexdigest()

    def close(self) -> None:
        if self._pending:
            with contextlib.suppress(TraceWriteError):  # (kept in self.error)
                self.flush()
        if self._file:
            try:
                self._file.close()
            except OSError as e:
                self.error = TraceWriteError(self.path, e)
            self._file = None

    # -- one record per message ----------------------------------------------------

    def cfg(self, t: int, h: int, kind: str | int, pin: str, mode: int, pull: int, param: int, signal) -> None:
        """``kind``: its handler's name (``host/rig/hardware/peripherals.py``), a kind unknown its number."""
        record = {"t": t, "msg": "CFG", "handle": h, "kind": kind, "pin": pin, "mode": mode, "pull": pull}
        self.write({**record, "param": param, "signal": signal})

    # OUT, WAIT and STATE, a few every exchange, are kept as their numbers and formatted by
    # hand when written (every number a plain int: the encoder's bytes, sorted keys and no
    # spaces, at a fraction of its cost).

    def out(self, t: int, h: int, attr: int, value: int) -> None:
        self._pending.append((_out_line, (t, h, attr, value)))

    def wait(self, t: int, until: int, watch) -> None:
        self._pending.append((_wait_line, (t, until, watch)))
        if len(self._pending) >= KEPT_MAX:
            self.flush()  # (a link that sends no STATE: a board's)

    def state(self, t: int, base: int, horizon: int, changes, segments=()) -> None:
        """A STATE sent (``changes`` is not changed after): written now, with the
        exchange's records before it. ``segments``: the EDGES sent with it, whose edges the
        record lists among its changes as the firmware takes them (``F.merge_edges``): a
        STATE record is the changes the firmware took, segments or a change an edge."""
        if segments:
            changes = F.merge_edges(segments, changes)
        self._pending.append((_state_line, (t, base, horizon, changes)))
        self.flush()
        if self.idle is not None:
            self.idle()

    def seen(self, t: int, h: int, sample_no: int) -> None:
        self.write({"t": t, "msg": "SEEN", "handle": h, "sample": sample_no})

    def uart_tx(self, t: int, h: int, data: bytes) -> None:
        self.write({"t": t, "msg": "UART_TX", "handle": h, "data": data.hex()})

    def bus(self, t: int, h: int, op: int, address: int, wrote: bytes, reply: tuple, more=None) -> None:
        """A bus transfer and its ``reply`` (status, count, bytes read); ``more``: the
        transaction's bus, register and duration_us (host/rig/hardware/bustrace.py), for a bus's
        handle (a bitstream has none). ``replay`` answers a bus from these."""
        status, count, got = reply  # (kept as its values, made a line when written: as OUT's)
        self._pending.append((_bus_line, (t, h, op, address, wrote.hex(), status, count, got.hex(), more)))
        if len(self._pending) >= KEPT_MAX:
            self.flush()

    def i2ct_done(self, t: int, h: int, status: int, acks: int, got: bytes) -> None:
        """A controller's transaction on this board's I2CTarget, as it answered."""
        self.write({"t": t, "msg": "I2CT_DONE", "handle": h, "status": status, "count": acks, "read": got.hex()})

    def fault(self, t: int) -> None:
        self.write({"t": t, "msg": "FAULT"})

    def exit(self, t: int, kind: int, code: int) -> None:
        self.write({"t": t, "msg": "EXIT", "kind": kind, "code": code})

    def rollback(self, t: int) -> None:
        self.write({"t": t, "msg": "ROLLBACK"})


_encode = LinkLog._encode


def _as_is(line: str) -> str:
    return line


def _out_line(t, h, attr, value) -> str:
    name = OUT_ATTRS.get(attr)
    if name is not None and type(t) is int and type(h) is int and type(value) is int:
        return f'{{"attr":"{name}","handle":{h},"msg":"OUT","t":{t},"value":{value}}}\n'
    return _encode({"t": t, "msg": "OUT", "handle": h, "attr": OUT_ATTRS.get(attr, attr), "value": value}) + "\n"


def _wait_line(t, until, watch) -> str:
    if not watch and type(t) is int and type(until) is int:
        return f'{{"msg":"WAIT","t":{t},"until":{until},"watch":[]}}\n'
    watched = sorted(watch)
    if type(t) is int and type(until) is int and all(type(h) is int for h in watched):
        listed = ",".join(map(str, watched))
        return f'{{"msg":"WAIT","t":{t},"until":{until},"watch":[{listed}]}}\n'
    return _encode({"t": t, "msg": "WAIT", "until": until, "watch": watched}) + "\n"


def _bus_line(t, h, op, address, wrote, status, count, read, more) -> str:
    record = {"t": t, "msg": "BUS", "handle": h, "op": op, "address": address, "wrote": wrote}
    record.update(status=status, count=count, read=read)
    if more:
        record.update(more)
    return _encode(record) + "\n"


def _state_line(t, base, horizon, changes) -> str:
    if not changes and type(t) is int and type(base) is int and type(horizon) is int:
        return f'{{"base":{base},"changes":[],"horizon":{horizon},"msg":"STATE","t":{t},"to":"fw"}}\n'
    entries = [[ct, h, k, v, e.hex() if k == F.CH_BYTES else e] for ct, h, k, v, e in changes]
    if type(t) is int and type(base) is int and type(horizon) is int and all(_plain_ints(e) for e in entries):
        listed = ",".join(
            f'[{ct},{h},{k},{v},"{e}"]' if type(e) is str else f"[{ct},{h},{k},{v},{e}]" for ct, h, k, v, e in entries
        )
        return f'{{"base":{base},"changes":[{listed}],"horizon":{horizon},"msg":"STATE","t":{t},"to":"fw"}}\n'
    entries = {"t": t, "to": "fw", "msg": "STATE", "base": base, "horizon": horizon, "changes": entries}
    return _encode(entries) + "\n"


def _plain_ints(entry: list) -> bool:
    """A STATE change whose numbers are plain ints (and its bytes, CH_BYTES, hex text)."""
    ct, h, k, v, e = entry
    plain_extra = type(e) is str if k == F.CH_BYTES else type(e) is int
    return type(ct) is int and type(h) is int and type(k) is int and type(v) is int and plain_extra


class _NoLog(LinkLog):
    """A rig that does not trace: every record is dropped unmade."""

    digest = None
    error = None
    idle = None
    lines = 0

    def __init__(self):
        self.path = None

    def write(self, record: dict) -> None:
        pass

    def close(self) -> None:
        pass

    line = flush = cfg = out = wait = state = seen = uart_tx = bus = i2ct_done = fault = exit = rollback = (
        lambda self, *args: None
    )


NO_LOG = _NoLog()
