# Frozen into the harness's MicroPython: asyncio, as a board build has it, plus its
# pure-Python task queue (asyncio/task.py, which board builds leave out in favour of
# the C module _asyncio). The shim swaps it in: _asyncio compares ticks with the unix
# port's period and stamps tasks with the process clock, not the virtual one.
include("$(MPY_DIR)/extmod/asyncio")
package("asyncio", ("task.py",), base_path="$(MPY_DIR)/extmod", opt=3)
