# The firmware's own lib/machine.py, which takes the built-in's names from umachine.
import machine

pin = machine.Pin(15, machine.Pin.OUT)
pin.value(1)
print("R origin", repr(getattr(machine, "ORIGIN", "board")))
print("R pin", repr(pin.value()))
print("R umachine", repr(getattr(__import__("umachine"), "ORIGIN", "board")))
