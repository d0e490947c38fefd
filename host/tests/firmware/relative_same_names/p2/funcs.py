wait_for = "p2.funcs"  # a name asyncio fetches lazily from its own funcs
