from umachine import *  # noqa: F403

ORIGIN = "firmware"  # machine is an extensible built-in: a file of its name wins
