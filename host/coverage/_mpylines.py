# Run by MicroPython's settrace variant (host/coverage/lines.py), never by CPython: the lines
# a file's bytecode has, as MicroPython compiles it (a `while True:` has none: the compiler
# drops a constant test). The file is compiled and its module's code object caught by the
# trace function at the "call" event (py/vm.c FRAME_ENTER -> py/profile.c
# mp_prof_frame_enter, before the first instruction), which raises so that none of its
# lines runs; then every code object under it is walked through co_consts. One file per
# process: the raise leaves py/profile.c's mp_prof_is_executing set, so no later frame
# would be traced (or caught).
# co_lnotab is py/objcode.c's raw_code_lnotab: pairs of (bytecode offset step, line step),
# the line step the low byte of an unsigned difference (so a step back wraps: read signed).
# argv: one file. Prints a JSON list of its lines; nothing for a file that does not compile.
import json
import sys


class _Caught(Exception):
    pass


_codes = []


def _catch(frame, event, arg):
    _codes.append(frame.f_code)
    raise _Caught


def _lines(code, n_lines, out):
    line = code.co_firstlineno
    out.add(line)
    table = code.co_lnotab
    for i in range(1, len(table), 2):
        step = table[i]
        if step >= 128 and line + step - 256 >= 1:
            step -= 256
        line += step
        if 1 <= line <= n_lines:
            out.add(line)
    for const in code.co_consts:
        if type(const).__name__ == "code":
            _lines(const, n_lines, out)


def main(name):
    try:
        with open(name) as f:
            text = f.read()
        code = compile(text, name, "exec")
    except Exception:
        return
    sys.settrace(_catch)
    try:
        exec(code, {"__name__": "_mpylines"})
    except _Caught:
        pass
    sys.settrace(None)
    if _codes:
        lines = set()
        _lines(_codes[0], text.count("\n") + 1, lines)
        print(json.dumps(sorted(lines)))


if __name__ == "__main__":
    main(sys.argv[1])
