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
ground truth               ``real 64``            SI units as the column names say
=========================  =====================  ========================================

Time is virtual: ``$timescale 1us``, ``#t`` is microseconds since the run started.
When a variable changes more than once at the same microsecond, the last value is
written.
"""

import heapq
import itertools
import re

TIMESCALE = "1us"
_ID_FIRST, _ID_LAST = 33, 126  # printable ASCII, as identifier codes


def write_vcd(path, *, top: str, comment: str, signals: dict, initial: dict, events, truth) -> None:
    """``signals``: name -> {"role", "kind"}; ``events``: (t_us, name, value) in time
    order; ``truth``: (t_us, {column: value}) in time order (iterated twice). Both may be
    iterables that read from disk: nothing here holds them whole."""
    columns = sorted({k for _t, row in truth for k in row if k != "t_us"})
    ids: dict[tuple[str, str], str] = {}
    tree: dict = {}
    for name, info in signals.items():
        _insert(tree, [info["role"] + "s", *name.split(":", 1)[-1].split(".")], ("sig", name, info["kind"]))
    for col in columns:
        _insert(tree, ["truth", col], ("truth", col, "real"))
    with open(path, "w", encoding="ascii", errors="replace") as f:
        f.write(f"$version mpy-fil $end\n$comment {_clean(comment)} $end\n$timescale {TIMESCALE} $end\n")
        f.write(f"$scope module {_ident(top)} $end\n")
        _declare(f, tree, ids)
        f.write("$upscope $end\n$enddefinitions $end\n")
        kinds = {name: info["kind"] for name, info in signals.items()}
        sigs = ((t, 0, ("sig", name), kinds.get(name, "level"), v) for t, name, v in events)
        reals = ((t, 1, ("truth", col), "real", row[col]) for t, row in truth for col in columns if col in row)
        # (streamed, not held: both come in time order, so a merge gives what a stable sort would)
        merged = heapq.merge(sigs, reals, key=lambda e: (e[0], e[1]))
        # $dumpvars holds every variable's value at time 0, after the changes at time 0
        state = {
            ids[("sig", name)]: _value(info["kind"], initial.get(name), ids[("sig", name)])
            for name, info in signals.items()
        }
        state.update({ids[("truth", col)]: _value("real", None, ids[("truth", col)]) for col in columns})
        change = next(merged, None)
        while change is not None and change[0] <= 0:
            _t, _order, key, kind, value = change
            if key in ids:
                state[ids[key]] = _value(kind, value, ids[key])
            change = next(merged, None)
        f.write("#0\n$dumpvars\n" + "\n".join(state.values()) + "\n$end\n")
        if change is not None:
            _write_changes(f, itertools.chain([change], merged), ids)


def _write_changes(f, merged, ids) -> None:
    for t, changes in itertools.groupby(merged, key=lambda e: e[0]):
        last: dict[str, str] = {}
        for _t, _order, key, kind, value in changes:
            code = ids.get(key)
            if code is not None:
                last[code] = _value(kind, value, code)
        if last:
            f.write(f"#{t}\n")
            f.write("\n".join(last.values()) + "\n")


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


def _declare(f, tree: dict, ids: dict) -> None:
    for name, node in tree.items():
        if isinstance(node, dict):
            f.write(f"$scope module {name} $end\n")
            _declare(f, node, ids)
            f.write("$upscope $end\n")
            continue
        code = _code(len(ids))
        ids[(node[0], node[1])] = code
        f.write(f"$var {_var_type(node[2])} {code} {name} $end\n")


_SAME_AS = {"uart": "bytes", "pwm": "duty"}  # plant input kinds recorded as these


def _var_type(kind: str) -> str:
    kind = _SAME_AS.get(kind, kind)
    if kind == "real":
        return "real 64"
    if kind in ("u16", "duty"):
        return "integer 32"
    if kind == "bytes":
        return "wire 8"
    return "wire 1"


def _value(kind: str, value, code: str) -> str:
    kind = _SAME_AS.get(kind, kind)
    if kind == "real":
        return f"r{float(value):.9g} {code}" if value is not None else f"r0 {code}"
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


def _clean(text: str) -> str:
    return text.replace("$end", "(end)").replace("\n", " ")
