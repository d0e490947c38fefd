"""A plant that plays a fixed timeline of output signals and records its inputs.

For tests of the shim and the link, and for replaying a recorded sensor stream:
outputs change exactly when the script says; every input the firmware drives is
logged with its virtual time.
"""

from sim_plant.plant import NEVER_US, Change, Plant


class ScriptedPlant(Plant):
    def __init__(self, script=(), *, outputs: dict[str, str], inputs: dict[str, str], initial: dict | None = None):
        self.script = sorted((int(t), name, value) for t, name, value in script)
        self.outputs = dict(outputs)
        self.inputs = dict(inputs)
        unknown = {name for _, name, _ in self.script} - set(self.outputs)
        if unknown:
            raise KeyError(f"script drives unknown outputs {sorted(unknown)}")
        self.initial = dict(initial or {})
        self.reset(0)

    def reset(self, seed: int) -> None:
        self._t_us = 0
        self._next = 0
        self.values = {name: self.initial.get(name, 0) for name in self.outputs}
        self.log: list[tuple[int, str, object]] = []

    @property
    def t_us(self) -> int:
        return self._t_us

    def set_input(self, name: str, value) -> None:
        if name not in self.inputs:
            raise KeyError(f"ScriptedPlant has no input {name!r}")
        self.log.append((self._t_us, name, value))

    def next_change_us(self) -> int:
        return self.script[self._next][0] if self._next < len(self.script) else NEVER_US

    def advance_to(self, t_us: int, limit: int = 0) -> list[Change]:
        changes = []
        while self._next < len(self.script) and self.script[self._next][0] <= t_us:
            t, name, value = self.script[self._next]
            if limit and len(changes) >= limit and t > self._t_us:
                return changes  # stopped after the instant that reached the limit
            self._t_us = t
            self._next += 1
            if self.outputs[name] == "bytes":
                changes.append(Change(t, name, value))
            elif self.outputs[name] == "u16" or self.values[name] != value:
                self.values[name] = value
                changes.append(Change(t, name, value))
        self._t_us = max(self._t_us, t_us)
        return changes

    def output(self, name: str):
        return self.values[name]

    def truth(self) -> dict:
        return {"t_us": self._t_us, "inputs": list(self.log)}
