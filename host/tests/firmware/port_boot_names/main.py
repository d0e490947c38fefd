# What the port's frozen _boot.py left in __main__: Kitronik's demos call machine.Pin
# without importing machine, which works on a Pico.
print("R names", sorted(n for n in ("machine", "rp2", "gc", "vfs", "bdev") if n in globals()))
if "machine" in globals():
    print("R pin", machine.Pin.IRQ_RISING)  # noqa: F821
