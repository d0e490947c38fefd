"""The lines of ``signals.csv`` and ``truth.csv`` as ``csv.writer`` writes them (the excel
dialect, "\\n" lines), made by hand where ``csv`` would neither quote nor change a field, by
``csv`` itself where it would: the folder's writers at the end and the streamed files
(:mod:`host.artefacts.streaming`) make the same bytes."""

import csv
import io
import re

_CSV_NUMBERS = {int, float, type(None)}  # (csv writes these as repr, None as "": never quoted)
_CSV_SPECIAL = re.compile(r'[,"\r\n]')
_UNSET = object()


def csv_free(text: str) -> bool:
    """Whether ``csv.writer`` writes ``text`` as it is: no delimiter, quote or line break
    in it, and not empty (an empty field alone on its line is quoted)."""
    return bool(text) and _CSV_SPECIAL.search(text) is None


class CsvLine:
    """One row as ``csv.writer`` writes it."""

    def __init__(self):
        self._buffer = io.StringIO()
        self._writer = csv.writer(self._buffer, lineterminator="\n")

    def __call__(self, row) -> str:
        buffer = self._buffer
        buffer.seek(0)
        buffer.truncate()
        self._writer.writerow(row)
        return buffer.getvalue()


class SignalLines:
    """``signals.csv``'s lines (``t_us,signal,value``) of the events given, call after call;
    ``in_order`` turns False once an event comes before the one before it."""

    def __init__(self):
        self._free: dict = {}  # signal name -> whether csv leaves it as it is
        self._csv_line = CsvLine()
        self._t_last = None
        self.in_order = True

    def __call__(self, events) -> str:
        lines = []
        free, t_last = self._free, self._t_last
        for t, name, value in events:
            if t_last is not None and t < t_last:
                self.in_order = False
            t_last = t
            kind = type(value)
            plain = free.get(name)
            if plain is None:
                plain = free[name] = type(name) is str and csv_free(name)
            if plain and type(t) is int and (kind is int or kind is float or (kind is str and csv_free(value))):
                lines.append(f"{t},{name},{value}\n")
            else:
                lines.append(self._csv_line((t, name, value)))
        self._t_last = t_last
        return "".join(lines)


class TruthLines:
    """``truth.csv``'s lines (``t_us`` then ``columns``: None as "", a float as its repr, an
    int as ``str``) of the rows given, call after call. A value equal to its column's last
    one (the same type, and not a float zero: -0.0 == 0.0 but reads otherwise) takes the
    same text; a row with a value other than a plain int, float or None is csv's."""

    def __init__(self, columns: list[str]):
        self.columns = list(columns)
        self._shown = [_UNSET] * (len(self.columns) + 1)  # each column's last value written ...
        self._texts = [""] * len(self._shown)  # ... and its text
        self._csv_line = CsvLine()

    def header(self) -> str:
        return self._csv_line(["t_us", *self.columns])

    def __call__(self, rows) -> str:
        lines = []
        columns = self.columns
        for t, row in rows:
            values = [t, *map(row.get, columns)]
            line = self._line(values)
            lines.append(self._csv_line(values) if line is None else line)
        return "".join(lines)

    def _line(self, values: list) -> str | None:
        shown, texts = self._shown, self._texts
        parts = []
        for i, v in enumerate(values):
            before = shown[i]
            if type(v) is type(before) and v == before and (v != 0 or type(v) is not float):
                parts.append(texts[i])
                continue
            if type(v) not in _CSV_NUMBERS:
                return None
            text = "" if v is None else repr(v)
            shown[i], texts[i] = v, text
            parts.append(text)
        return ",".join(parts) + "\n"
