"""The host side of the firmware's peripherals: one handler per CFG kind, the wiring of
board pins to plant signals, inputs and outputs, PIO, buses (their image, their trace, the
poll that never ends)."""
