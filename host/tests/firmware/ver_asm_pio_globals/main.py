# rp2.asm_pio whose program raises while it is assembled (it names one of the module's own
# globals, which its body cannot see), caught: from 1.28 the module's globals are back as
# they were (ports/rp2/modules/rp2.py, asm_pio's try/finally); before, they are left as
# the PIO names alone, and the firmware's own names are gone (a NameError at their next use).
import rp2
import sys

print("R version", sys.implementation.version[:2])
COUNT = 3
seen = "mine"


def bad():
    set(x, COUNT)  # noqa: F821  (x is the PIO's; COUNT is not seen while assembling)


try:
    rp2.asm_pio()(bad)
    print("R raised", False)
except NameError:
    result = "NameError"
try:
    print("R after", [result, seen])
except NameError:
    print("R after", ["NameError", "globals lost"])
