"""Where the firmware runs: the ``Target`` interface and the unix port's, the sandbox around
it, the board's flash for one run, the firmware's files, its heap and the board's own time."""
