"""A strict reader of the VCD subset the harness writes (IEEE 1364 §18), for tests: it
rejects what a wave viewer would trip on (unknown identifiers, values that do not fit
their variable, time going backwards, unbalanced scopes)."""

import re
import shutil
import subprocess
from dataclasses import dataclass, field
from pathlib import Path

SCALAR = re.compile(r"^([01xXzZ])(\S+)$")
VECTOR = re.compile(r"^[bB]([01xXzZ]+) (\S+)$")
REAL = re.compile(r"^[rR](\S+) (\S+)$")
STRING = re.compile(r"^s(\S*) (\S+)$")  # GTKWave's extension: text, C escapes for white space


class VcdError(AssertionError):
    pass


@dataclass
class Var:
    type: str
    width: int
    code: str
    path: str  # scope.scope.name


@dataclass
class Vcd:
    sections: dict = field(default_factory=dict)  # $timescale, $version, $comment text
    vars: dict = field(default_factory=dict)  # path -> Var
    times: list = field(default_factory=list)
    changes: dict = field(default_factory=dict)  # path -> [(t, value)]

    def timeline(self, path: str) -> list:
        return self.changes[path]

    def final(self, path: str):
        return self.changes[path][-1][1]


def read_vcd(text: str) -> Vcd:
    vcd = Vcd()
    by_code = _read_header(text.split(), vcd)
    body = text.split("$enddefinitions", 1)[1].split("$end", 1)[1]
    _read_body(body, vcd, by_code)
    return vcd


def _read_header(tokens: list[str], vcd: Vcd) -> dict[str, list[Var]]:
    """The declarations up to $enddefinitions; returns the variables by identifier code."""
    i = 0
    scopes: list[str] = []
    by_code: dict[str, list[Var]] = {}
    while True:
        if i >= len(tokens):
            raise VcdError("no $enddefinitions")
        tok = tokens[i]
        if tok in ("$timescale", "$version", "$comment", "$date"):
            end = tokens.index("$end", i)
            vcd.sections[tok] = " ".join(tokens[i + 1 : end])
            i = end + 1
        elif tok == "$scope":
            kind, name, end = tokens[i + 1 : i + 4]
            if kind != "module" or end != "$end":
                raise VcdError(f"bad $scope at token {i}: {tokens[i : i + 4]}")
            scopes.append(name)
            i += 4
        elif tok == "$upscope":
            if not scopes or tokens[i + 1] != "$end":
                raise VcdError(f"unbalanced $upscope at token {i}")
            scopes.pop()
            i += 2
        elif tok == "$var":
            _declare(tokens[i : i + 6], i, scopes, vcd, by_code)
            i += 6
        elif tok == "$enddefinitions":
            if tokens[i + 1] != "$end":
                raise VcdError("$enddefinitions without $end")
            if scopes:
                raise VcdError(f"scopes left open: {scopes}")
            return by_code
        else:
            raise VcdError(f"unexpected token {tok!r} in the header")


def _declare(tokens: list[str], i: int, scopes: list[str], vcd: Vcd, by_code: dict) -> None:
    _var, type_, width, code, name, end = tokens
    if end != "$end" or type_ not in ("wire", "reg", "integer", "real", "event", "string"):
        raise VcdError(f"bad $var at token {i}: {tokens}")
    var = Var(type_, int(width), code, ".".join([*scopes, name]))
    if var.path in vcd.vars:
        raise VcdError(f"variable {var.path} declared twice")
    vcd.vars[var.path] = var
    vcd.changes[var.path] = []
    by_code.setdefault(code, []).append(var)


def _read_body(body: str, vcd: Vcd, by_code: dict) -> None:
    t = None
    for line in body.split("\n"):
        line = line.strip()
        if not line or line in ("$dumpvars", "$end"):
            continue
        if line.startswith("#"):
            new_t = int(line[1:])
            if t is not None and new_t <= t:
                raise VcdError(f"time goes from #{t} to #{new_t}")
            t = new_t
            vcd.times.append(t)
            continue
        if t is None:
            raise VcdError(f"value change before the first time stamp: {line!r}")
        kind, m = _match(line)
        if m is None:
            raise VcdError(f"unreadable value change {line!r} at #{t}")
        value, code = m.group(1), m.group(2)
        if code not in by_code:
            raise VcdError(f"value change {line!r} at #{t} for an undeclared identifier")
        for var in by_code[code]:
            vcd.changes[var.path].append((t, _parse_value(kind, value, line, var)))


def _parse_value(kind: str, value: str, line: str, var: Var):
    if (kind == "string") != (var.type == "string"):
        raise VcdError(f"value {line!r} does not fit {var.type} {var.path}")
    if kind == "string":
        return value.encode("ascii").decode("unicode_escape")
    if kind == "real":
        if var.type != "real":
            raise VcdError(f"real value {line!r} for {var.type} {var.path}")
        return float(value)
    if kind == "vector":
        if var.type == "real" or len(value) > var.width:
            raise VcdError(f"vector {line!r} does not fit {var.type} {var.width} {var.path}")
        if set(value) <= {"0", "1"}:
            return int(value, 2)
        return value.lower()[0] if len(set(value.lower())) == 1 else value  # x or z, left-extended
    if var.width != 1:
        raise VcdError(f"scalar {line!r} for {var.width}-bit {var.path}")
    return int(value) if value in "01" else value


def _match(line: str):
    for pattern, kind in ((VECTOR, "vector"), (REAL, "real"), (STRING, "string"), (SCALAR, "scalar")):
        m = pattern.match(line)
        if m:
            return kind, m
    return None, None


GTKWAVE_MISSING = (
    "expected GTKWave's vcd2fst and fst2vcd on PATH, found none: `make setup` installs Debian's gtkwave "
    "package when run as root; otherwise run `sudo apt-get install -y gtkwave`"
)


def gtkwave_round_trip(vcd_path: Path, work: Path) -> str:
    """The VCD as GTKWave reads it: converted to its FST format by vcd2fst, written back
    by fst2vcd. Raises AssertionError (naming the package) when GTKWave is missing or
    rejects the file."""
    vcd2fst, fst2vcd = shutil.which("vcd2fst"), shutil.which("fst2vcd")
    if not (vcd2fst and fst2vcd):
        raise AssertionError(GTKWAVE_MISSING)
    fst = work / (vcd_path.stem + ".fst")
    done = subprocess.run([vcd2fst, str(vcd_path), str(fst)], capture_output=True, text=True, timeout=60)
    if done.returncode != 0 or not fst.is_file():
        raise AssertionError(f"vcd2fst rejected {vcd_path}: {done.stdout}{done.stderr}")
    back = subprocess.run([fst2vcd, str(fst)], capture_output=True, text=True, timeout=60)
    if back.returncode != 0:
        raise AssertionError(f"fst2vcd could not read {fst}: {back.stderr}")
    return back.stdout
