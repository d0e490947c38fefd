"""The firmware's outputs: each OUT and UART_TX applied to the plant at its virtual time,
shown to the budgets that watch the pin, and recorded. The message's handler
(``host/rig/loop/messages.py``) hands it to its handle's peripheral with these.

The handle's kind's handler (``host/rig/hardware/peripherals.py``) says what its output does: a
pin's level, a PWM's duty (a waveform, with its frequency, when the plant input is of
kind ``pwm``), a UART's bytes. A pin wired to a plant input drives it; a pin wired to a
probe is watched by budgets only; a pin wired to nothing is recorded as ``pin.<name>``.
"""

from host.artefacts.recorder import ROLE_ACTUATOR, ROLE_PIN, ROLE_PROBE


class Outputs:
    def __init__(self, plant, wiring, hooks, recorder):
        self.plant = plant
        self.plant_inputs = plant.inputs
        self.wiring = wiring
        self.level_hooks = hooks.level
        self.recorder = recorder

    def record(self, t: int, info, value, kind: str) -> None:
        """A firmware output, as the plant's input (or the probe, or the bare pin) saw it;
        ``kind``: a signal kind (``F.SIG_LEVEL``, ``F.SIG_DUTY``, ``F.SIG_BYTES``)."""
        if info.probe:
            self.recorder.command(t, info.signal, value, role=ROLE_PROBE, kind=kind)
        elif info.signal in self.plant_inputs:
            self.recorder.command(t, info.signal, value, role=ROLE_ACTUATOR, kind=kind)
        else:
            self.recorder.command(t, f"pin.{info.board_name or info.key}", value, role=ROLE_PIN, kind=kind)
