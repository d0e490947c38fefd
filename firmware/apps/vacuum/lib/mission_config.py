# The mission as a file on the board (/mission.json): where odometry starts, the goals in
# turn, the PID gains, and which of the seed's listed bugs to build in. Every key is
# optional; an unknown key or bug stops the robot before it moves. Pure Python.
#
#   {"start": [x_cm, y_cm, phi_deg], "goals": [[x_cm, y_cm], ...],
#    "gains": [kp, ki, kd], "bugs": ["mean_filter_no_reset", "heading_no_wrap",
#    "derivative_in_ms"]}
import json

from go_to_goal import GAIN_SETS

BUGS = ("mean_filter_no_reset", "heading_no_wrap", "derivative_in_ms")
DEFAULTS = {"start": (0.0, 0.0, 0.0), "goals": ((150.0, 150.0),), "gains": GAIN_SETS[0], "bugs": ()}


def parse(text):
    """The mission from the file's text, defaults filled in; ValueError names a bad key."""
    given = json.loads(text) if text.strip() else {}
    unknown = [k for k in given if k not in DEFAULTS]
    if unknown:
        raise ValueError("mission.json: unknown key %s (keys: %s)" % (unknown[0], ", ".join(DEFAULTS)))
    mission = dict(DEFAULTS)
    mission.update(given)
    for bug in mission["bugs"]:
        if bug not in BUGS:
            raise ValueError("mission.json: unknown bug %r (bugs: %s)" % (bug, ", ".join(BUGS)))
    if len(mission["start"]) != 3 or len(mission["gains"]) != 3:
        raise ValueError("mission.json: start is [x_cm, y_cm, phi_deg] and gains [kp, ki, kd]")
    return mission


def load(path="mission.json"):
    try:
        with open(path) as f:
            return parse(f.read())
    except OSError:  # no file on the board: the defaults (the seed's first test)
        return parse("")
