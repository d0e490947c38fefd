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
"""

import copy
from typing import NamedTuple

import numpy as np


class Change(NamedTuple):
    """One output event: at ``t_us``, signal ``name`` took ``value``."""

    t_us: int
    name: str
    value: object


NEVER_US = 1 << 62
"""A time later than any run: returned by :meth:`Plant.next_change_us` when nothing is due."""


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
