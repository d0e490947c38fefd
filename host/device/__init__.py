"""Boards, real and virtual: ``make flash`` (mpy-cross + mpremote), the virtual board
(the unix port behind a pty, with a board REPL) and processor in the loop."""
