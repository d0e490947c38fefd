"""A firmware's code read without running it: the pins it makes and their names, checked
against a rig's wiring (``mpy-fil check``), and the starting rig file of ``mpy-fil init``."""
