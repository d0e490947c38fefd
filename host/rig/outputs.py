"""The firmware's outputs: each OUT and UART_TX applied to the plant at its virtual time,
shown to the budgets that watch the pin, and recorded.

A pin wired to a plant input drives it (a level, a PWM duty, UART bytes; a PWM's
frequency too when the input is of kind ``pwm``, a waveform); a pin wired to
a probe is watched by budgets only; a pin wired to nothing is recorded as ``pin.<name>``.
"""

from host.artefacts.recorder import ROLE_ACTUATOR, ROLE_PIN, ROLE_PROBE
from host.link import frames as F


class Outputs:
    def __init__(self, plant, wiring, hooks, recorder):
        self.plant = plant
        self.plant_inputs = plant.inputs
        self.wiring = wiring
        self.level_hooks = hooks.level
        self.recorder = recorder

    def out(self, t: int, h: int, attr: int, value: int) -> None:
        info = self.wiring.handles[h]
        signal = info.signal
        if attr == F.OUT_FREQ:
            info.freq = value
            if info.level and self.plant_inputs.get(signal) == "pwm":
                self.plant.set_pwm(signal, value, info.level)
            return
        if self.recorder is not None:
            kind = "duty" if info.kind == F.CFG_PWM else "level"
            self._record(t, info, 0 if attr == F.OUT_DEINIT else value, kind)
        last, info.level = info.level, value
        if signal is None:
            return
        if attr == F.OUT_LEVEL and (info.probe or signal in self.plant_inputs):
            hooks = self.level_hooks.get(signal)
            if hooks:
                changed = last is not None and last != value
                for call in hooks:
                    call(t, signal, value, changed)
        if signal not in self.plant_inputs:
            return  # a probe: only the harness watches it
        if info.kind == F.CFG_PWM:
            duty = value if attr == F.OUT_DUTY else 0  # (deinit: the line held low)
            if self.plant_inputs[signal] == "pwm":  # the plant takes the waveform
                self.plant.set_pwm(signal, info.freq, duty)
            else:
                self.plant.set_input(signal, duty)
        elif attr == F.OUT_LEVEL:
            self.plant.set_input(signal, value)

    def uart_tx(self, t: int, h: int, data: bytes) -> None:
        info = self.wiring.handles[h]
        if self.recorder is not None:
            self._record(t, info, data, "bytes")
        kind = self.plant_inputs.get(info.signal)
        if kind == "uart":  # the plant times the bytes on the line at the baud rate
            self.plant.send_bytes(info.signal, data, info.freq)
        elif kind is not None:
            self.plant.set_input(info.signal, data)

    def _record(self, t: int, info, value, kind: str) -> None:
        """A firmware output, as the plant's input (or the probe, or the bare pin) saw it."""
        if info.probe:
            self.recorder.command(t, info.signal, value, role=ROLE_PROBE, kind=kind)
        elif info.signal in self.plant_inputs:
            self.recorder.command(t, info.signal, value, role=ROLE_ACTUATOR, kind=kind)
        else:
            self.recorder.command(t, f"pin.{info.board_name or info.key}", value, role=ROLE_PIN, kind=kind)
