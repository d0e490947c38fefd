# The heap a firmware finds as it starts: its board's.
import gc

gc.collect()
print("R free", gc.mem_free())
