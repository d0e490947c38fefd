# int.to_bytes(signed=True): py/objint.c's int_to_bytes takes its arguments by position only
# up to 1.28 (MP_DEFINE_CONST_FUN_OBJ_VAR_BETWEEN, "TODO: Support signed"); 1.29 takes signed=.
import sys

print("R version", sys.implementation.version[:2])
try:
    print("R signed", (-2).to_bytes(2, "big", signed=True))
except TypeError as e:
    print("R signed", ["TypeError", str(e)])
print("R positional", (-2).to_bytes(2, "big"))
