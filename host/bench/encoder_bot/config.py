# Settings of this robot (a board keeps them beside main.py).
TARGET_CPS = 5000  # each wheel's speed, in encoder counts per second (both wheels: 10,000 edges a second)
RUN_MS = 3000  # drive this long, then stop and print the counts
