"""The contract between the host's rig and every plant.

Time is an integer number of microseconds (``t_us``) of virtual time. A plant is a
piecewise-constant-input system: the rig sets inputs (actuator signals as the
board drives them) at the current time, asks when the next output change is due,
and advances to a time of its choosing. Outputs are the electrical signals a board
sees, by name:

===================  ======================================================
kind                 value
===================  ======================================================
``level``            0 or 1 (a digital pin: encoder channel, bumper switch)
``u16``              0..65535 (an ADC reading as ``ADC.read_u16`` returns it)
``bytes``            bytes received by a UART at that time
===================  ======================================================

A *change* is reported when a level flips, when a sampled signal (``u16``) takes a
new sample (even if the value is the same: a new sample is an event the firmware is
expected to consume), or when bytes arrive.

:class:`Plant` is the whole interface the host calls; the host never asks a plant what it
has (no ``getattr``/``hasattr``). What every plant answers has a safe default here (no
buses, no parts, no world, the plant itself when ``unwrapped``). What only some plants
can do is a **capability**, declared in ``capabilities`` (``CAPABILITIES`` names each and
the methods it brings: ``pwm``: ``set_pwm``; ``uart``: ``send_bytes``; ``buses``:
``bus_transfer``; ``bitstream``; ``pose``: ``pose_at``; ``controls``: ``set_control``); the
host checks the flag, not the method. A class that declares a capability without its
methods, or has the methods undeclared, is refused when it is made; a plant with an input
of kind ``pwm`` or ``uart`` without the capability is refused when it is built
(:func:`check_contract`, called by the host's ``build_plant`` and the rig file's loader).
A wrapper (the fault schedule, :class:`sim_plant.faults.FaultyPlant`) answers
``unwrapped`` with the plant inside it.
"""

import copy
from typing import NamedTuple

import numpy as np


class Change(NamedTuple):
    """One output event: at ``t_us``, signal ``name`` took ``value``."""

    t_us: int
    name: str
    value: object


class ReleasedAt(int):
    """An io line's input let go a little after the instant it is given: -1 (released) to
    anything that takes it as a number, and ``at_us`` to a part that times from it (a PIO
    state machine's ``pindirs`` change, seen by the host's look-ahead before its cycle comes:
    ``host/rig/hardware/pio_out.py``; ``sim_plant.catalogue.qtr`` starts the discharge there)."""

    at_us: float

    def __new__(cls, at_us: float):
        value = super().__new__(cls, -1)
        value.at_us = at_us
        return value

    def __reduce__(self):
        return ReleasedAt, (self.at_us,)


class LevelAt(int):
    """A level (0 or 1) a PIO state machine drives a little after the instant it is given,
    seen by the host's look-ahead before its cycle comes (``host/rig/hardware/pio_out.py``):
    the level to anything that takes it as a number, and ``at_us`` to a part that takes
    each edge at its own instant (its signal in :attr:`Plant.timed_inputs`: a clocked
    serial chip, ``sim_plant.catalogue.tlc1543``)."""

    at_us: float

    def __new__(cls, level: int, at_us: float):
        value = super().__new__(cls, level)
        value.at_us = at_us
        return value

    def __reduce__(self):
        return LevelAt, (int(self), self.at_us)


NEVER_US = 1 << 62
"""A time later than any run: returned by :meth:`Plant.next_change_us` when nothing is due."""

PWM, UART, BUSES, BITSTREAM, POSE, CONTROLS = "pwm", "uart", "buses", "bitstream", "pose", "controls"
CAPABILITIES = {
    PWM: ("set_pwm",),
    UART: ("send_bytes",),
    BUSES: ("bus_transfer",),
    BITSTREAM: ("bitstream",),
    POSE: ("pose_at",),
    CONTROLS: ("set_control",),
}
"""Capability -> the methods a plant that declares it implements (and only such a plant)."""
INPUT_NEEDS = {"pwm": PWM, "uart": UART}
"""An input of this kind needs this capability (the host gives it a waveform, bytes at a baud rate)."""


class ContractError(TypeError):
    """A plant class or plant that breaks the contract: the message names the plant, the
    capability and the method."""


def _implemented(cls, capability: str) -> bool:
    return all(getattr(cls, m) is not getattr(Plant, m) for m in CAPABILITIES[capability])


def check_contract(plant: "Plant") -> "Plant":
    """``plant`` as built, checked: its declared capabilities are known and implemented,
    and each input of kind ``pwm`` or ``uart`` has its capability; a ContractError if not."""
    inner = plant.unwrapped
    declared = plant.capabilities
    unknown = sorted(set(declared) - set(CAPABILITIES))
    if unknown:
        raise ContractError(
            f"{type(inner).__name__}: unknown capability {unknown[0]!r} (known: {', '.join(CAPABILITIES)})"
        )
    _check_class(type(inner), declared)
    for name, kind in plant.inputs.items():
        need = INPUT_NEEDS.get(kind)
        if need is not None and need not in declared:
            raise ContractError(
                f"{type(inner).__name__}: input {name!r} is of kind {kind!r}, which needs the {need!r} capability "
                f"({', '.join(CAPABILITIES[need])}); its capabilities: {', '.join(sorted(declared)) or 'none'}"
            )
    return plant


def _check_class(cls, declared) -> None:
    for capability, methods in CAPABILITIES.items():
        has = _implemented(cls, capability)
        if capability in declared and not has:
            raise ContractError(f"{cls.__name__} declares {capability!r} but does not implement {', '.join(methods)}")
        if has and capability not in declared:
            raise ContractError(
                f"{cls.__name__} implements {', '.join(methods)} but does not declare {capability!r} in capabilities"
            )


class Plant:
    """Base class and contract. Subclasses fill in the physics.

    ``inputs`` and ``outputs`` map signal names to their kind (``level``, ``u16``,
    ``duty``, ``bytes``); the rig's wiring connects board pins to these names.
    """

    inputs: dict[str, str] = {}
    outputs: dict[str, str] = {}
    zero_delay = False
    """True when an input may change an output at the same instant (a wire from a board
    output to a board input): the shim then syncs a read that follows a write."""
    timed_inputs: frozenset = frozenset()
    """The inputs whose parts take a PIO's edges each at its own instant (:class:`LevelAt`),
    not the burst's last level at the frame's: a clock and the data it clocks."""
    capabilities: frozenset = frozenset()
    """What it can do beyond levels and samples (``CAPABILITIES``)."""
    world = None
    """The walls it moves among (a ``sim_plant.world.World``), if any: the trace draws them."""
    start_pose = None
    """Its start pose as given (x_m, y_m, heading_rad), or None: its world's own."""
    catalogue_parts: tuple = ()
    """The catalogue parts it is built from (``sim_plant.catalogue``), if any."""
    rng = None
    """Its random generator (a numpy Generator), if it draws: a trial of a read on a copy of
    a chip restores it (host/rig/hardware/busimage.py)."""

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        if isinstance(cls.__dict__.get("capabilities"), property) or getattr(cls, "WRAPS", False):
            return  # (a wrapper's are its inner plant's: checked when it is built)
        _check_class(cls, cls.capabilities)

    def reset(self, seed: int) -> None:
        """Start over at ``t_us = 0`` with a generator seeded by ``seed``."""
        raise NotImplementedError

    @property
    def t_us(self) -> int:
        raise NotImplementedError

    def set_input(self, name: str, value: int) -> None:
        """Apply an actuator signal from the current time on."""
        raise NotImplementedError

    def next_change_us(self) -> int:
        """Earliest time (> ``t_us``) at which an output may change, given the inputs.

        It may be a check point at which nothing changes after all; it is never later
        than the real next change.
        """
        raise NotImplementedError

    def advance_to(self, t_us: int, limit: int = 0) -> list[Change]:
        """Advance to ``t_us`` and return the changes in ``(t, t_us]``, in time order.

        With ``limit`` > 0, stop early at the instant whose changes bring the count to
        ``limit`` or more (all of that instant's changes are returned; ``t_us`` is then
        that instant). Callers that need every event at its own time advance to
        :meth:`next_change_us` step by step.
        """
        raise NotImplementedError

    def output(self, name: str) -> object:
        """Current value of an output signal."""
        raise NotImplementedError

    def truth(self) -> dict:
        """Ground truth for tests (pose, contacts, ...); never seen by the firmware."""
        raise NotImplementedError

    def sample_period_us(self, signal: str) -> int | None:
        """How often ``signal`` takes a new sample, if at a fixed period (a budget's default)."""
        return None

    # -- what every plant answers (safe defaults) --------------------------------------

    @property
    def edge_counters(self) -> tuple:
        """Its encoders whose edges :meth:`advance_edges` may hand as segments (each an
        ``sim_plant.physics.encoder._EdgeCounter`` with the plain ``emit``): none here."""
        return ()

    def advance_edges(self, t_us: int, limit: int, segs: list, seg_room: int = 0) -> list[Change]:
        """:meth:`advance_to`, the edges of :attr:`edge_counters` between two of its other
        events going to ``segs`` as segments (``sim_plant.engine.RobotPlant``); here, all of
        them as changes."""
        return self.advance_to(t_us, limit)

    @property
    def unwrapped(self) -> "Plant":
        """The plant itself; a wrapper's (the fault schedule's) inner plant."""
        return self

    @property
    def fault_schedule(self) -> tuple:
        """The faults a wrapper applies (each with ``kind`` and ``fields``): none here."""
        return ()

    @property
    def summary(self) -> str:
        """One line for ``mpy-fil check``: its class by default."""
        return type(self).__name__

    def describe(self) -> dict | None:
        """Its body and parts as data, for the trace header and the report; None: nothing to say."""
        return None

    def wired_signals(self) -> list | None:
        """The signals one board of several is wired to (a board's view of a shared plant,
        host/rig/boardview.py); None: the plant is one board's whole."""
        return None

    def driven_inputs(self) -> set:
        """Inputs something inside the plant drives (a PWM expander's): no pin need be wired to them."""
        return set()

    def bus_devices(self) -> tuple:
        """The devices on its buses (each with ``bus``, ``address``, ``label``)."""
        return ()

    def bus_names(self) -> dict:
        """Bus name -> the names of the parts on it."""
        return {}

    def chip_selects(self) -> dict:
        """A part on SPI with a chip-select input -> (its bus, that input)."""
        return {}

    def tied_chip_selects(self) -> set:
        """The chip-select inputs the rig ties low (no pin can be wired to them)."""
        return set()

    def bus_notes(self, bus: str) -> list:
        """What the devices on ``bus`` have to say in the run's output (each once)."""
        return []

    def bus_device(self, bus: str, address: int | None):
        """The device on ``bus`` at ``address`` (None on SPI: the one selected), or None."""
        return None

    def coverage_grid(self):
        """Its floor coverage grid (``cell_m``, ``half_width_m``), if it keeps one."""
        return None

    def footprint(self) -> tuple:
        """The circles (x_m, y_m, r_m on the body) a body that moves occupies, to check its
        start pose against its world's walls; none: nothing to check."""
        return ()

    def displays(self) -> list:
        """(label, width, height, [(t_us, picture)]) of each display it shows pictures on."""
        return []

    # -- capabilities: called only when declared ---------------------------------------

    def _lacks(self, capability: str):
        return ContractError(f"{type(self.unwrapped).__name__} has no {capability!r} capability")

    def set_pwm(self, name: str, freq_hz: int, duty_u16: int) -> None:
        """``pwm``: a PWM waveform on input ``name`` from now on."""
        raise self._lacks(PWM)

    def send_bytes(self, name: str, data: bytes, baud: int) -> None:
        """``uart``: bytes a UART sends on input ``name`` at ``baud``, from now."""
        raise self._lacks(UART)

    def bus_transfer(self, bus: str, op: int, address: int, n_read: int, data: bytes, unclocked=frozenset()) -> tuple:
        """``buses``: one BUS frame's transfer, (status, count, bytes read); ``unclocked``:
        the SPI clock inputs whose pins are not the SPI's at this instant."""
        raise self._lacks(BUSES)

    def bitstream(self, name: str, timing_ns: tuple, data: bytes) -> None:
        """``bitstream``: ``machine.bitstream`` on the pin wired to input ``name``."""
        raise self._lacks(BITSTREAM)

    def pose_at(self, t_us: int) -> tuple[float, float, float]:
        """``pose``: the robot's pose (x_m, y_m, heading_rad) at ``t_us``."""
        raise self._lacks(POSE)

    def set_control(self, name: str, control: str, value) -> None:
        """``controls``: part ``name``'s ``control`` is ``value`` from now on."""
        raise self._lacks(CONTROLS)

    def close(self) -> None:
        """Let go of what the plant holds outside itself (an external chip's program:
        ``sim_plant/catalogue/external.py``), as the rig stops; it stays readable."""

    def snapshot(self):
        """The whole mutable state, to :meth:`restore` later (the host rewinds speculative
        batches with it). This default copies the plant's attributes; a plant that knows
        its state better (``RobotPlant``) overrides both."""
        gens: list = []
        return _copy_state(self.__dict__, gens), [(g, g.bit_generator.state) for g in gens]

    def restore(self, snap) -> None:
        state, gens = snap
        self.__dict__.clear()
        self.__dict__.update(state)
        for gen, gen_state in gens:
            gen.bit_generator.state = gen_state


_IMMUTABLE = (int, float, str, bytes, bool, type(None), frozenset)


def _copy_state(value, gens: list):
    """A deep copy of plant state that is cheap for what plants hold (numbers, tuples of
    numbers, small lists and dicts, component objects); numpy Generators are kept by
    reference and their bit-generator state is saved in ``gens`` instead."""
    if isinstance(value, _IMMUTABLE):
        return value
    if isinstance(value, list):
        return [_copy_state(v, gens) for v in value]
    if isinstance(value, dict):
        return {k: _copy_state(v, gens) for k, v in value.items()}
    if isinstance(value, tuple):
        return value if all(isinstance(v, _IMMUTABLE) for v in value) else tuple(_copy_state(v, gens) for v in value)
    if isinstance(value, np.random.Generator):
        gens.append(value)
        return value
    if isinstance(value, np.ndarray):
        return value.copy()
    if hasattr(value, "__dict__") and not isinstance(value, type):
        clone = copy.copy(value)
        clone.__dict__.update(_copy_state(value.__dict__, gens))
        return clone
    return copy.deepcopy(value)
