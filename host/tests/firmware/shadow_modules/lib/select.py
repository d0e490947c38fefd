from uselect import *  # noqa: F403

ORIGIN = "firmware"  # select is an extensible built-in: a file wins
