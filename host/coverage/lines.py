"""Lines as MicroPython runs them (docs/coverage.md).

coverage.py reads a source with CPython's parser: every statement is a line, and an arc
joins each to the next. MicroPython's compiler leaves some statements without bytecode (a
``while True:`` has none: it drops the constant test), so its tracer never reports them,
and coverage.py would call them never run. :func:`micropython_lines` asks MicroPython
itself which lines of a file have bytecode (``_mpylines.py`` on the settrace variant: the
file compiled, never run); :func:`bridged` then turns each arc the tracer recorded that
CPython's parser does not know (``6 -> 8``, over a ``while True:`` on line 7) into the
parser's path between its ends through lines MicroPython has no code for (``6 -> 7``,
``7 -> 8``). A line with code that did not run stays missed; a line without code is
marked run exactly when the firmware went through it.
"""

import json
import subprocess
from collections import deque
from pathlib import Path

SCRIPT = Path(__file__).with_name("_mpylines.py")
TIMEOUT_S = 30.0
_cache: dict[tuple, frozenset | None] = {}


def micropython_lines(source: Path, interpreter: Path) -> frozenset | None:
    """The lines of ``source`` that have bytecode in MicroPython (the settrace variant
    ``interpreter``), or None when it cannot tell (a file that does not compile)."""
    source = Path(source)
    try:
        stat = source.stat()
    except OSError:
        return None
    key = (str(source), stat.st_mtime_ns, stat.st_size, str(interpreter))
    if key not in _cache:
        _cache[key] = _ask(source, interpreter)
    return _cache[key]


def _ask(source: Path, interpreter: Path) -> frozenset | None:
    try:
        done = subprocess.run(
            [str(interpreter), str(SCRIPT), str(source)],
            capture_output=True,
            text=True,
            timeout=TIMEOUT_S,
            stdin=subprocess.DEVNULL,
        )
        lines = json.loads(done.stdout) if done.returncode == 0 and done.stdout.strip() else None
    except (OSError, subprocess.TimeoutExpired, ValueError):
        return None
    if not isinstance(lines, list) or not all(type(n) is int for n in lines):
        return None
    return frozenset(lines)


def cpython_arcs(source: Path) -> set[tuple[int, int]] | None:
    """The arcs coverage.py's parser finds in ``source`` (what its report counts)."""
    from coverage.exceptions import CoverageException
    from coverage.parser import PythonParser

    try:
        parser = PythonParser(text=Path(source).read_text(encoding="utf-8"), filename=str(source))
        parser.parse_source()
        return set(parser.arcs())
    except (CoverageException, OSError, SyntaxError, ValueError):
        return None


def bridged(arcs: set, possible: set, with_code: frozenset) -> set:
    """``arcs`` with each one ``possible`` does not hold replaced by the shortest path of
    possible arcs between its ends whose lines in between have no code in MicroPython
    (not in ``with_code``); an arc with no such path is kept as it is."""
    following: dict[int, list[int]] = {}
    for a, b in possible:
        following.setdefault(a, []).append(b)
    out = set()
    for arc in arcs:
        path = None if arc in possible else _path(arc, following, with_code)
        out.update(path or (arc,))
    return out


def _path(arc: tuple[int, int], following: dict, with_code: frozenset) -> list | None:
    start, end = arc
    came: dict[int, int] = {}
    queue = deque([start])
    while queue:
        here = queue.popleft()
        for there in following.get(here, ()):
            if there in came or there == start:
                continue
            came[there] = here
            if there == end:
                steps, node = [], end
                while node != start:
                    steps.append((came[node], node))
                    node = came[node]
                return steps[::-1]
            if there > 0 and there not in with_code:  # (only through lines MicroPython has no code for)
                queue.append(there)
    return None
