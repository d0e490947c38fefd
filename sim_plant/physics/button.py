"""Push-buttons pressed at scripted times (a rig's start button, a user's presses): the
engine part behind the catalogue's ``button``."""

from sim_plant.engine import Part
from sim_plant.plant import NEVER_US, Change


class Buttons(Part):
    """Push-buttons to ground with a pull-up, pressed at scripted times. With
    ``bounce_us``, each press and release chatters: the new level, the old one a quarter
    of the way in, the new one again half way, as a worn contact does."""

    FIXED_STATE = ("events", "inputs", "outputs")

    def __init__(self, names, presses, bounce_us: int = 0):
        self.outputs = {f"button.{n}": "level" for n in names}
        events = []
        for name, t_press_s, t_release_s in presses:
            if name not in names:
                raise ValueError(f"presses: no button {name!r} (buttons: {', '.join(names) or 'none'})")
            if not 0 <= t_press_s < t_release_s:
                raise ValueError(f"presses: {name} pressed at {t_press_s} s, released at {t_release_s} s")
            for t_s, level in ((t_press_s, 0), (t_release_s, 1)):
                t_us = round(t_s * 1e6)
                events.append((t_us, f"button.{name}", level))
                if bounce_us > 0:
                    events.append((t_us + bounce_us // 4, f"button.{name}", 1 - level))
                    events.append((t_us + bounce_us // 2, f"button.{name}", level))
        self.events = sorted(events)
        self.i = 0
        self.next_us = self.events[0][0] if self.events else NEVER_US

    def initial_outputs(self) -> dict:
        return dict.fromkeys(self.outputs, 1)

    def fire(self, t_us: int, plant, out: list) -> None:
        while self.i < len(self.events) and self.events[self.i][0] <= t_us:
            _t, name, level = self.events[self.i]
            out.append(Change(t_us, name, level))
            self.i += 1
        self.next_us = self.events[self.i][0] if self.i < len(self.events) else NEVER_US


class Jumper(Part):
    """A jumper from a board input to ground: the pin reads 0 when it is fitted."""

    FIXED_STATE = True

    def __init__(self, name: str, fitted: bool):
        self.outputs = {name: "level"}
        self.level = 0 if fitted else 1

    def initial_outputs(self) -> dict:
        return {next(iter(self.outputs)): self.level}
