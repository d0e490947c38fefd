"""The firmware's heap (``[interpreter] heap_size``, docs/rig-file.md) and the shim's share.

On a board, ``machine``, ``time`` and the link are C in flash; in the loop they are the
shim's Python, in the unix port's one heap with the firmware. The interpreter gets
``heap_size`` plus the shim's share, so that the firmware's ``gc.mem_free()`` is about
its board's heap and a firmware that fills it meets MemoryError where a board's would.
"""

# The shim's share: its start-up, compiling machine the biggest moment of it (measured: the
# interpreter needs 240K to 256K all told), then what it keeps (its modules, asyncio in
# virtual time, machine: 100K) and its reserve for a full heap (host/shim/_hil.py,
# make_room). The firmware's heap_size is set apart in one piece before that start-up
# (host/shim/_hilboot.py, _firmware_room), so the start-up runs in this share alone; the
# shim then holds what is left of the share and lets the firmware's piece go (_board_heap):
# the firmware finds heap_size free and in one piece, as on a board. (The coverage tracer
# runs through the start-up too: host/rig/targets/firmware.py adds its share to both sides.)
SHIM_HEAP_BYTES = 320 * 1024
# The least heap_size a rig file takes: what a small firmware importing machine, time and
# asyncio, with pins, an ADC, a PWM, a Timer, an IRQ and two tasks, needs (measured: 12K;
# pico_bot's main.py, 16K to 24K), tested at exactly this size by
# host/tests/test_heap_size.py.
HEAP_MIN_BYTES = 24 * 1024
HEAP_MAX_BYTES = 1024 * 1024 * 1024
