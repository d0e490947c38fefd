"""The link log (``trace.jsonl``): what crossed the link, decoded, one JSON object per
line, in virtual time.

It holds the link messages and what the plant reported, never wall-clock figures, so
the same (app, board, plant, seed, commit) gives the same bytes. The firmware's console
goes to its own file, since its pipe is not ordered with the link. ``digest`` is a
SHA-256 of the lines, kept even when no file is written. A rig that does not trace logs
to :data:`NO_LOG`, which keeps nothing.

The file is line-buffered: each record reaches the file as it is written, so a run killed
outright (SIGKILL) leaves every record to its last whole line. A write that fails (a full
disk) raises :class:`~host.artefacts.integrity.TraceWriteError` once; the file stays as it
was cut (:attr:`LinkLog.error`) and later records are only hashed.
"""

import hashlib
import json
from pathlib import Path

from host.artefacts.integrity import TraceWriteError
from host.link import frames as F

OUT_ATTRS = {F.OUT_LEVEL: "level", F.OUT_DUTY: "duty_u16", F.OUT_FREQ: "freq", F.OUT_DEINIT: "deinit"}


class LinkLog:
    def __init__(self, path: Path | None = None):
        self.path = path
        self._file = open(path, "w", encoding="utf-8", buffering=1) if path else None  # noqa: SIM115
        self._hash = hashlib.sha256()
        self.lines = 0
        self.error: TraceWriteError | None = None

    _encode = json.JSONEncoder(separators=(",", ":"), sort_keys=True).encode  # (json.dumps makes one per call)

    def write(self, record: dict) -> None:
        self.line(self._encode(record) + "\n")

    def line(self, line: str) -> None:
        """One record already in JSON (the hot messages: written by hand, the same bytes)."""
        self._hash.update(line.encode())
        self.lines += 1
        if self._file:
            try:
                self._file.write(line)
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
    def digest(self) -> str:
        return self._hash.hexdigest()

    def close(self) -> None:
        if self._file:
            try:
                self._file.close()
            except OSError as e:
                self.error = TraceWriteError(self.path, e)
            self._file = None

    # -- one record per message ----------------------------------------------------

    def cfg(self, t: int, h: int, kind: str | int, pin: str, mode: int, pull: int, param: int, signal) -> None:
        """``kind``: its handler's name (``host/rig/peripherals.py``), a kind unknown its number."""
        record = {"t": t, "msg": "CFG", "handle": h, "kind": kind, "pin": pin, "mode": mode, "pull": pull}
        self.write({**record, "param": param, "signal": signal})

    # OUT, WAIT and STATE, a few every exchange, are formatted by hand when every number is
    # a plain int: the encoder's bytes (sorted keys, no spaces) at a fraction of its cost.

    def out(self, t: int, h: int, attr: int, value: int) -> None:
        name = OUT_ATTRS.get(attr)
        if name is not None and type(t) is int and type(h) is int and type(value) is int:
            self.line(f'{{"attr":"{name}","handle":{h},"msg":"OUT","t":{t},"value":{value}}}\n')
        else:
            self.write({"t": t, "msg": "OUT", "handle": h, "attr": OUT_ATTRS.get(attr, attr), "value": value})

    def wait(self, t: int, until: int, watch) -> None:
        watched = sorted(watch)
        if type(t) is int and type(until) is int and all(type(h) is int for h in watched):
            listed = ",".join(map(str, watched))
            self.line(f'{{"msg":"WAIT","t":{t},"until":{until},"watch":[{listed}]}}\n')
        else:
            self.write({"t": t, "msg": "WAIT", "until": until, "watch": watched})

    def state(self, t: int, base: int, horizon: int, changes) -> None:
        entries = [[ct, h, k, v, e.hex() if k == F.CH_BYTES else e] for ct, h, k, v, e in changes]
        if type(t) is int and type(base) is int and type(horizon) is int and all(_plain_ints(e) for e in entries):
            listed = ",".join(
                f'[{ct},{h},{k},{v},"{e}"]' if type(e) is str else f"[{ct},{h},{k},{v},{e}]"
                for ct, h, k, v, e in entries
            )
            self.line(f'{{"base":{base},"changes":[{listed}],"horizon":{horizon},"msg":"STATE","t":{t},"to":"fw"}}\n')
        else:
            self.write({"t": t, "to": "fw", "msg": "STATE", "base": base, "horizon": horizon, "changes": entries})

    def seen(self, t: int, h: int, sample_no: int) -> None:
        self.write({"t": t, "msg": "SEEN", "handle": h, "sample": sample_no})

    def uart_tx(self, t: int, h: int, data: bytes) -> None:
        self.write({"t": t, "msg": "UART_TX", "handle": h, "data": data.hex()})

    def bus(self, t: int, h: int, op: int, address: int, wrote: bytes, reply: tuple, more=None) -> None:
        """A bus transfer and its ``reply`` (status, count, bytes read); ``more``: the
        transaction's bus, register and duration_us (host/rig/bustrace.py), for a bus's
        handle (a bitstream has none). ``replay`` answers a bus from these."""
        status, count, got = reply
        record = {"t": t, "msg": "BUS", "handle": h, "op": op, "address": address, "wrote": wrote.hex()}
        self.write({**record, "status": status, "count": count, "read": got.hex(), **(more or {})})

    def fault(self, t: int) -> None:
        self.write({"t": t, "msg": "FAULT"})

    def exit(self, t: int, kind: int, code: int) -> None:
        self.write({"t": t, "msg": "EXIT", "kind": kind, "code": code})

    def rollback(self, t: int) -> None:
        self.write({"t": t, "msg": "ROLLBACK"})


def _plain_ints(entry: list) -> bool:
    """A STATE change whose numbers are plain ints (and its bytes, CH_BYTES, hex text)."""
    ct, h, k, v, e = entry
    plain_extra = type(e) is str if k == F.CH_BYTES else type(e) is int
    return type(ct) is int and type(h) is int and type(k) is int and type(v) is int and plain_extra


class _NoLog(LinkLog):
    """A rig that does not trace: every record is dropped unmade."""

    digest = None
    error = None

    def __init__(self):
        self.path = None
        self.lines = 0

    def write(self, record: dict) -> None:
        pass

    def close(self) -> None:
        pass

    line = cfg = out = wait = state = seen = uart_tx = fault = exit = rollback = lambda self, *args: None


NO_LOG = _NoLog()
