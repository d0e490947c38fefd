ORIGIN = "firmware"  # under lib/: the frozen module comes first on a board
