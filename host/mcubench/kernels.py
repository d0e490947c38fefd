# Kernels whose times on boards are published (docs/mcu-time.md, "Calibration"), written
# here after their descriptions: each runs once on the counting interpreter, which prints
# what it executed (_hilfast.counts) as one JSON line per kernel. MicroPython only.
import json
import sys

import _hilfast


def _kernel(op):
    # the loop body `C = p[1] <op> p[2]` over range(p[0]), p a list: one function per
    # operator, compiled from the same text
    src = "def k(p):\n    for _ in range(p[0]):\n        C = p[1] %s p[2]\n" % op
    g = {}
    exec(src, g)
    return g["k"]


def mandelbrot(p):
    # a 81 x 31 grid of c = (u/30 - 2) + (v/15 - 1)j, each iterated z = z*z + c up to
    # p[0] times or until |z| > 4, drawn into a string
    limit = p[0]

    def inside(c):
        z = 0
        for _ in range(limit):
            z = z * z + c
            if abs(z) > 4:
                return False
        return True

    out = ""
    for v in range(31):
        for u in range(81):
            out += " " if inside((u / 30 - 2) + (v / 15 - 1) * 1j) else "#"
        out += "\n"
    return out


def pi_digits(p):
    # pi to p[0] digits with 8 guard digits by the series of arcsin(1/2) in integers
    digits = p[0]
    guard = 8
    one = 10 ** (digits + guard)
    t = c = 3 * one
    n, na, d, da = 1, 0, 0, 24
    while t > 1:
        n, na, d, da = n + na, na + 8, d + da, da + 32
        t = t * n // d
        c += t
    return c // 10**guard


KERNELS = {
    "int_add": (_kernel("+"), [100000, 12345678, 56781234]),
    "int_mul": (_kernel("*"), [100000, 12345678, 56781234]),
    "int_div": (_kernel("/"), [100000, 99999991, 45481]),
    "float_add": (_kernel("+"), [100000, 12345678.1234, 56781234.5678]),
    "float_mul": (_kernel("*"), [100000, 12345678.1234, 56781234.5678]),
    "float_div": (_kernel("/"), [100000, 99999991.2345, 45481.1357]),
    "float_pow": (_kernel("**"), [100000, 1234.5678, 2.3456]),
    "mandelbrot_100": (mandelbrot, [100]),
    "mandelbrot_500": (mandelbrot, [500]),
    "pi_1000": (pi_digits, [1000]),
}


def main(names):
    import gc

    for name in names or KERNELS:
        fn, p = KERNELS[name]
        gc.collect()
        c0 = _hilfast.counts()
        fn(p)
        c1 = _hilfast.counts()
        out = {"name": name, "ops": [b - a for a, b in zip(c0["ops"], c1["ops"])]}
        for k in c1:
            if k != "ops":
                out[k] = c1[k] - c0[k]
        print(json.dumps(out))


main(sys.argv[1:])
