"""A plant from a body and a list of parts (a rig file's ``[plant] body = ...`` and its
``[[plant.parts]]``): :func:`assemble` checks the table whole, naming the table and
the field of the first mistake (``[[plant.parts]] #2 (sonar_rear) period_us: expected
...``; parts are counted from 1 in the file's order), and builds a :class:`PartsPlant`.
"""

import os
from pathlib import Path

import tomllib

from sim_plant import catalogue
from sim_plant.buses import BusDevice, BusSet, on_spi
from sim_plant.catalogue.base import MOUNT_KEYS, MOUNT_SPEC, BodyType, Build, PartsError
from sim_plant.contacts import ContactMonitor
from sim_plant.controls import ControlError, ControlTimeline
from sim_plant.engine import RobotPlant
from sim_plant.names import nearest, unknown
from sim_plant.option_table import FileName, Name
from sim_plant.physics.coverage import CoverageRecorder
from sim_plant.plant import BITSTREAM, BUSES, CONTROLS, POSE, PWM, UART

PART_KEYS = ("kind", "name", "mount")
POSE_KEYS = ("x_m", "y_m", "theta_rad")
MAX_PARTS = 64


class PartsPlant(RobotPlant):
    """A :class:`~sim_plant.engine.RobotPlant` whose drive, encoders and parts come from
    a body and catalogue parts; rebuilt afresh at each reset."""

    capabilities = frozenset((POSE, PWM, UART, BUSES, BITSTREAM, CONTROLS))
    FIXED_STATE = (*RobotPlant.FIXED_STATE, "catalogue_parts")

    def __init__(self, body, parts: list, sources: tuple = ()):
        self.body = body
        self.sources = tuple(sources)  # a user's catalogue sources (folders' absolute paths, modules)
        self.catalogue_parts = list(parts)
        self.zero_delay = any(p.zero_delay for p in self.catalogue_parts)
        self._reads_empty = frozenset(n for p in self.catalogue_parts if p.reads_empty for n in p.signals())
        self.timed_inputs = frozenset(
            n for p in self.catalogue_parts if p.timed for n, (way, _kind) in p.signals().items() if way == "in"
        )
        super().__init__()

    def _build(self) -> None:
        build = Build(body=dict(self.body.options), rng=self.rng, controls=ControlTimeline())
        for part in self.catalogue_parts:
            try:
                part.add(build)
            except ValueError as e:
                raise PartsError(f"{part.label} {e}") from None
        body = self.body
        self.world, pose = body.world_and_pose(self.rng) if body.draws_world else body.world_and_pose()
        self.start_pose = pose  # (x_m, y_m, heading_rad) at reset
        self.drive = self.body.drive(build, pose)
        monitor = self.body.contact_monitor(build)
        self.encoders = build.encoders
        self.bus_set = BusSet([p for p in build.parts if isinstance(p, BusDevice)])
        self.parts = ([monitor] if monitor is not None else []) + build.parts + self.body.recorders(build, self.world)
        self.controls = build.controls
        self.parts.append(self.controls)
        self._check_driven()

    def _check_driven(self) -> None:
        """Every input a part drives is another part's: a PWM expander's channel (``drives``),
        a button's or a battery divider's line going on to a chip (``shares``); each part's
        ``targets``, named by its ``targets_option``."""
        inputs = set(self.drive.inputs).union(*(p.inputs for p in self.parts))
        labels = {p.name: p.label for p in self.catalogue_parts}
        for device in self.bus_set.devices:
            supply = getattr(device, "battery", None)  # (an INA219's battery part)
            if supply and not any(getattr(p, "label", None) == supply and hasattr(p, "v") for p in self.parts):
                batteries = [p.label for p in self.parts if hasattr(p, "v") and getattr(p, "label", None)]
                known = unknown(supply, batteries, what="batteries")
                raise PartsError(
                    f"{labels.get(device.label, device.label)} battery: no battery part named {supply!r} {known}"
                )
        for part in self.parts:
            targets = getattr(part, "targets", ())
            if not targets:
                continue
            others = inputs.difference(part.inputs)
            for name in targets:
                if name != "-" and name not in others:
                    raise PartsError(
                        f"{labels.get(part.label, part.label)} {getattr(part, 'targets_option', 'drives')}: expected "
                        f"inputs of the plant's parts ({', '.join(sorted(others))}), got {name!r}"
                    )

    def bus_devices(self) -> tuple:
        return tuple(self.bus_set.devices)

    def coverage_grid(self):
        """The grid of its ``coverage`` part (or its tracked body's recorder), once started."""
        return next((p.grid for p in self.parts if isinstance(p, CoverageRecorder) and p.grid is not None), None)

    def footprint(self) -> tuple:
        """Its contact monitor's circles (a point without one); none for a body that does not move."""
        if not self.body.moves:
            return ()
        monitor = next((p for p in self.parts if isinstance(p, ContactMonitor)), None)
        return tuple(monitor.circles) if monitor is not None else ((0.0, 0.0, 0.0),)

    def displays(self) -> list:
        """Each engine part that keeps its frames (``display_frames()``: an ``ssd1306``)."""
        return [(p.label, *p.display_frames()) for p in self.parts if callable(getattr(p, "display_frames", None))]

    def driven_inputs(self) -> set:
        """The inputs a bus device drives (a PWM expander's channels): no pin needs wiring to them."""
        return {n for d in self.bus_set.devices for n in getattr(d, "targets", ()) if n != "-"}

    def input_owner(self, name: str):
        """The engine part (or the drive) that takes input ``name``."""
        where = self._input_route[name]
        return self.drive if where < 0 else self.parts[where]

    def _react(self, t: int) -> bool:
        return self.body.react(self, t)

    def _reacts(self) -> bool:
        return type(self.body).react is not BodyType.react

    def carry_to(self, pose) -> None:
        """Someone lifts the robot and sets it down at ``pose`` (x_m, y_m, theta_rad) now
        (for test scenarios; the firmware is not told). A coverage path jumps (no swath
        between the two places); the walls are checked at once where it was set down."""
        if not self.body.moves:
            raise PartsError(f"carry_to: a {self.body.kind} does not move")
        t = self._t_us
        body = self.drive.body
        body.constraints = ()
        body.rebase(t, tuple(float(v) for v in pose))
        for part in self.parts:
            if isinstance(part, CoverageRecorder):
                part.jump(t, self)
            elif isinstance(part, ContactMonitor):  # what it touches where it was set down, at once
                part.check_us = t
        self._motion_changed(t)

    def set_control(self, name: str, control: str, value) -> None:
        """Part ``name``'s ``control`` (``PartType.CONTROLS``) is ``value`` from now on (a
        scenario's ``set-control``); a ControlError names the part's controls."""
        part = next((p for p in self.catalogue_parts if p.name == name), None)
        if part is None:
            with_controls = [p.name for p in self.catalogue_parts if p.CONTROLS]
            close = unknown(name, with_controls).rpartition(")")[2]
            raise ControlError(f"no part {name!r} (parts with controls: {', '.join(with_controls) or 'none'}){close}")
        change = part.control_change(control, value)  # (checks the control and the value)
        self.controls.set(self._t_us, name, control, value, change)
        self._reschedule()

    def restore(self, snap) -> None:
        super().restore(snap)
        if self.controls.entries:  # (a control set after the snapshot is due again)
            self._reschedule()

    def _wire_part(self, name: str):
        where = self._input_route.get(name, -1)
        part = self.parts[where] if where >= 0 else None
        if not hasattr(part, "send_bytes"):
            raise KeyError(f"{type(self).__name__} has no wire input {name!r} (a wire's .in, a uart_wire's .line)")
        return part

    def set_pwm(self, name: str, freq_hz: int, duty_u16: int) -> None:
        """A PWM on a wire's (or a buzzer's) input from now on (freq in Hz, duty 0..65535)."""
        where = self._input_route.get(name, -1)
        part = self.parts[where] if where >= 0 else None
        (part if hasattr(part, "set_pwm") else self._wire_part(name)).set_pwm(name, freq_hz, duty_u16, self._t_us)
        self._reschedule()

    def send_bytes(self, name: str, data: bytes, baud: int) -> None:
        """Bytes a UART sends on a UART wire at ``baud``, from now (after what is on it)."""
        where = self._input_route.get(name, -1)  # (the wire's part: _wire_part, without its call)
        send = getattr(self.parts[where], "send_bytes", None) if where >= 0 else None
        if send is None:
            send = self._wire_part(name).send_bytes  # (raises: no wire input of that name)
        send(name, data, baud, self._t_us)
        self._reschedule()

    def bus_transfer(self, bus: str, op: int, address: int, n_read: int, data: bytes, unclocked=frozenset()) -> tuple:
        """A bus transfer (a BUS frame, ``sim_plant.buses``) at the plant's time, against the
        devices on ``bus``: (status, count, bytes read). It may change what the devices do
        next (a data-ready line that falls, a rate written). ``unclocked``: SPI clock inputs
        whose chips the transfer does not reach (``BusSet.transfer``)."""
        if self._motion_pending:
            self._settle()
        on = self.bus_set.bus(bus)
        for device in on.takers:
            device.take_in(self)
        result = self.bus_set.transfer(self._t_us, bus, op, address, n_read, data, unclocked)
        for device in on.passers:
            device.pass_on(self)
        self._reschedule()
        return result

    def bus_notes(self, bus: str) -> list:
        """What the devices on ``bus`` have to say in the run's output (each once): a
        write to a register a chip's model does not honour."""
        notes = []
        for device in self.bus_set.bus(bus).devices:
            if getattr(device, "notes", None):
                notes += device.take_notes()
        return notes

    def bus_device(self, bus: str, address: int | None):
        """The device on ``bus`` at ``address`` (on SPI, None: the one selected), or None."""
        devices = self.bus_set.on(bus)
        if address is None:
            return next((d for d in devices if d.selected), None)
        return next((d for d in devices if d.address == address), None)

    def bitstream(self, name: str, timing_ns: tuple, data: bytes) -> None:
        """``machine.bitstream`` on the pin wired to input ``name`` from now: the part that
        takes it (a ``ws2812_strip``'s ``.din``) decodes it; another part's input ignores it."""
        part = self.input_owner(name) if name in self._input_route else None
        if hasattr(part, "bitstream"):
            part.bitstream(self._t_us, timing_ns, data)
            self._reschedule()

    def chip_selects(self) -> dict:
        """A part on SPI with a chip-select input (not tied low) -> (its bus, that input):
        ``check`` warns of one the wiring leaves out (it is never selected)."""
        selects = {}
        for part in self.catalogue_parts:
            cs = f"{part.name}.cs"
            if _on_spi(part) and cs in part.signals():
                selects[part.name] = (part.options["bus"], cs)
        return selects

    def tied_chip_selects(self) -> set:
        """The chip-select inputs the rig ties low (``cs = "low"``): no pin can be wired to them."""
        return {f"{p.name}.cs" for p in self.catalogue_parts if _on_spi(p) and p.options.get("cs") == "low"}

    def bus_names(self) -> dict:
        """Bus name -> the names of the parts on it (``check`` compares them with the firmware's)."""
        names: dict = {}
        for part in self.catalogue_parts:
            bus = part.options["bus"] if part.on_bus else None
            if bus:
                names.setdefault(bus, []).append(part.name)
        return names

    def advance_to(self, t_us: int, limit: int = 0) -> list:
        if limit and self.zero_delay:
            burst = self._burst(limit)
            if burst:
                return burst
        return self.advance_edges(t_us, limit, None)  # (RobotPlant.advance_to, without its call)

    def _burst(self, limit: int) -> list:
        """A wire's writes at this instant beyond ``limit`` (a loop of writes with no wait
        between them): given ``limit`` at a time, at this instant."""
        for part in self.parts:
            if getattr(part, "burst", 0) > limit:
                changes = part.take(limit)
                for change in changes:
                    self.values[change.name] = change.value
                self._reschedule()
                return changes
        return []

    def output(self, name: str) -> object:
        return b"" if name in self._reads_empty else super().output(name)

    def truth(self) -> dict:
        truth = super().truth()
        if not self.body.moves:
            for key in POSE_KEYS:
                truth.pop(key, None)
        return truth

    @property
    def summary(self) -> str:
        """``differential body with dc_motor motor_l, ...``: for ``mpy-fil check``."""
        parts = ", ".join(f"{p.kind} {p.name}" for p in self.catalogue_parts)
        return f"{self.body.kind} body with {parts or 'no parts'}"

    def describe(self) -> dict:
        """The body and the parts as data (a trace header keeps it; the report draws each
        part's declared views from it): ``{"body", "body_options", "parts": [{"kind",
        "name", "mount", "options"}]}``."""
        described = {
            "body": self.body.kind,
            "body_options": dict(self.body.options),
            "parts": [
                {
                    "kind": p.kind
                    if catalogue.resolve("parts", p.kind) is type(p)
                    else f"{type(p).__module__}:{type(p).__qualname__}",
                    "name": p.name,
                    "mount": dict(zip(MOUNT_KEYS, p.mount)),
                    "options": dict(p.options),
                }
                for p in self.catalogue_parts
            ],
        }
        if self.sources:  # (a report drawn later, in another process, finds a user's parts again)
            described["catalogue"] = list(self.sources)
        return described

    def signals(self) -> dict[str, tuple[str, str]]:
        """Every part's signals: full name -> (direction, kind)."""
        return {name: sig for part in self.catalogue_parts for name, sig in part.signals().items()}


def assemble(table: dict, base=None, rig_file=None) -> PartsPlant:
    """The plant a ``[plant]`` table with a ``body`` describes; :class:`PartsError` (a
    ValueError) naming the field of the first mistake. A key ``<part name>.<option>``
    (a world's, a test's or ``--param``'s) sets that option of the part of that name.
    ``catalogue``: a user's sources of parts, bodies and worlds (folders relative to
    ``base``, the rig file's folder, or module names: :func:`sim_plant.catalogue.add`).
    ``rig_file``: the file the table is from, which a part's messages at run time name."""
    sources = _add_sources(table, base)
    table, entries = _with_part_options(table)
    table = _with_world_files(table, base)
    entries = [_with_part_files(entry, base) for entry in entries]
    body = _body(table)
    parts, names = [], {}
    for i, entry in enumerate(entries, start=1):
        part = _part(i, entry)
        if part.name in names:
            raise PartsError(f"{part.label} name: {part.name!r} is part #{names[part.name]}'s name too")
        if part.needs_body and not body.moves:
            raise PartsError(f"{part.label} kind: a {part.kind} needs a body that moves, not a {body.kind}")
        names[part.name] = i
        if rig_file is not None:
            part.rig_file = str(rig_file)
        parts.append(part)
    _check_addresses(parts)
    return PartsPlant(body, parts, sources)


OWN_WORLDS = ("room", "furnished")
"""The differential body's own worlds: their options are the body's (room_w_m, obstacles, route)."""


def with_world(plant: dict, world) -> dict:
    """A rig file's ``[world]`` table (``kind`` and the world's options) as the body's
    ``world`` and ``world_options`` (the room's and the furnished room's options are the
    body's own): the world apart from the body, any body in any world."""
    if world is None:
        return plant
    if not isinstance(world, dict):
        raise PartsError(f"[world]: expected a table, got {world!r}"[:200])
    given = sorted(k for k in ("world", "world_options") if k in plant)
    if given:
        raise PartsError(f"[world]: the world is given in [plant] too ({', '.join(given)}): give it once, here")
    kind = world.get("kind")
    if not isinstance(kind, str):
        raise PartsError(f"[world] kind: expected a world's kind (docs/parts.md, 'World'), got {kind!r}"[:200])
    options = {k: v for k, v in world.items() if k != "kind"}
    for key in ("world", "world_options", "body", "parts", "catalogue"):
        if key in options:
            raise PartsError(f"[world] {key}: not a world's option (the world's kind is [world] kind)")
    if kind not in OWN_WORLDS:
        return {**plant, "world": kind, "world_options": options}
    twice = sorted(set(options) & set(plant))
    if twice:
        raise PartsError(f"[world] {twice[0]}: given in [plant] too: give it once")
    return {**plant, "world": kind, **options}


def _add_sources(table, base) -> None:
    sources = table.get("catalogue", []) if isinstance(table, dict) else []
    if not isinstance(sources, list):
        raise PartsError(f"[plant] catalogue: expected a list of folders or module names, got {sources!r}"[:200])
    return tuple(catalogue.add(source, base)[0] for source in sources)


def _with_world_files(table: dict, base) -> dict:
    """A catalogue world's file options (a :class:`~sim_plant.option_table.FileName`: the
    line course's ``picture``) as absolute paths, relative to ``base`` (the rig file's
    folder; the current folder without one)."""
    kind, options = table.get("world"), table.get("world_options")
    cls = catalogue.resolve("worlds", kind) if isinstance(kind, str) and isinstance(options, dict) else None
    if cls is None:
        return table
    files = {o.name for o in cls.OPTIONS if isinstance(o.spec, FileName)}
    given = {k: v for k, v in options.items() if k in files and not FileName().problem(v)}
    if not given:
        return table
    resolved = {k: os.path.abspath(Path(base or ".") / v) for k, v in given.items()}
    return {**table, "world_options": {**options, **resolved}}


def _with_part_files(entry, base):
    """A part's file options (a :class:`~sim_plant.option_table.FileName`: an external
    chip's ``command``) as absolute paths, relative to ``base`` (the rig file's folder)."""
    kind = entry.get("kind") if isinstance(entry, dict) else None
    try:
        cls = catalogue.resolve("parts", kind) if isinstance(kind, str) else None
    except PartsError:
        return entry  # (_part says what is wrong with it, naming its place)
    if cls is None:
        return entry
    files = {o.name for o in cls.OPTIONS if isinstance(o.spec, FileName)}
    given = {k: v for k, v in entry.items() if k in files and not FileName().problem(v)}
    if not given:
        return entry
    return {**entry, **{k: os.path.abspath(Path(base or ".") / v) for k, v in given.items()}}


def _on_spi(part) -> bool:
    """A bus part on an SPI bus (:func:`sim_plant.buses.on_spi`)."""
    return bool(part.on_bus and on_spi(part.options))


def _check_addresses(parts: list) -> None:
    """Two devices at one address on one bus: refused, naming both. (A chip on SPI has none:
    its chip select, or its clock input wired to a pin of its own, picks it out.)"""
    taken = {}
    for part in parts:
        bus = part.options["bus"] if part.on_bus else None
        if not bus or part.options.get("spi") or bus.startswith("spi"):
            continue
        where = (bus, part.options.get("address"))
        if where in taken:
            other = taken[where]
            at = f"0x{where[1]:02x}"
            raise PartsError(
                f"{part.label} address: {at} on bus {bus} is {other.label}'s too "
                f"(two devices at one address: give one its other address)"
            )
        taken[where] = part


def _with_part_options(table: dict) -> tuple[dict, list]:
    """The table without its ``<part>.<option>`` keys, and the part tables with them."""
    if not isinstance(table, dict):
        raise PartsError(f"[plant]: expected a table, got {table!r}"[:200])
    entries = table.get("parts", [])
    if not isinstance(entries, list) or len(entries) > MAX_PARTS:
        raise PartsError(f"[[plant.parts]]: expected a list of at most {MAX_PARTS} part tables, got {entries!r}"[:200])
    dotted = {k: v for k, v in table.items() if isinstance(k, str) and "." in k}
    if not dotted:
        return table, entries
    entries = [dict(e) if isinstance(e, dict) else e for e in entries]
    by_name = {e["name"]: e for e in entries if isinstance(e, dict) and isinstance(e.get("name"), str)}
    for key, value in dotted.items():
        name, option = key.split(".", 1)
        if name not in by_name or option in PART_KEYS:
            known = unknown(name, by_name, what="parts")
            raise PartsError(f"[plant] {_short(key)[1:-1]}: expected <part name>.<option> of a part {known}")
        by_name[name][option] = value
    return {k: v for k, v in table.items() if k not in dotted}, entries


def _body(table: dict):
    if not isinstance(table, dict):
        raise PartsError(f"[plant]: expected a table, got {table!r}"[:200])
    kind = table.get("body")
    cls = catalogue.resolve("bodies", kind) if isinstance(kind, str) else None
    if cls is None:
        bodies = catalogue.bodies()
        described = {k: c.doc for k, c in bodies.items()}
        raise PartsError(
            f"[plant] body: expected one of {', '.join(bodies)}, got {_short(kind)}{_hint(kind, described)}"
        )
    return cls(cls.checked(table, "[plant]", skip=("body", "parts", "catalogue")))


def _part(i: int, entry):
    label = f"[[plant.parts]] #{i}"
    if not isinstance(entry, dict):
        raise PartsError(f"{label}: expected a table, got {entry!r}"[:200])
    kind = entry.get("kind")
    cls = catalogue.resolve("parts", kind) if isinstance(kind, str) else None
    if cls is None:
        known = catalogue.parts()
        described = {k: c.doc for k, c in known.items()}
        raise PartsError(
            f"{label} kind: expected one of {', '.join(known)}, got {_short(kind)}{_hint(kind, described)}"
        )
    name = entry.get("name")
    problem = Name().problem(name)
    if problem or "." in name:
        problem = problem or f"expected no '.' (its signals are <name>.<signal>), got {name!r}"
        raise PartsError(f"{label} name: {problem}")
    label = f"{label} ({name})"
    mount = entry.get("mount", {})
    if not isinstance(mount, dict):
        raise PartsError(f"{label} mount: expected a table of {', '.join(MOUNT_KEYS)}, got {mount!r}"[:200])
    for key, value in mount.items():
        spec = MOUNT_SPEC.get(key)
        problem = spec.problem(value) if spec else f"expected one of {', '.join(MOUNT_KEYS)}"
        if problem:
            raise PartsError(f"{label} mount {key}: {problem}")
    options = cls.checked(entry, label, skip=PART_KEYS)
    try:
        part = cls(name, mount, options)
    except ValueError as e:
        raise PartsError(f"{label} {e}") from None
    part.label = label
    return part


def _hint(word, described: dict) -> str:
    """``; did you mean 'x'?``: the kinds nearest ``word`` by spelling and by what they are."""
    close = nearest(word, described, described)
    return f"; did you mean {' or '.join(map(repr, close))}?" if close else ""


def _short(value) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def rig_plant_table(path, parts: dict | None = None, **options) -> dict:
    """A rig file's ``[plant]`` table (a body and parts), with body ``options`` over its
    own and ``parts`` (a part's name -> options) over those parts' options: our robots'
    rig files, for tests and measurements that build their plants without a rig."""
    with open(path, "rb") as f:
        table = tomllib.load(f)["plant"]
    changed = dict(parts or {})
    entries = [{**entry, **changed.pop(entry.get("name"), {})} for entry in table.get("parts", [])]
    if changed:
        raise PartsError(f"{path}: no part named {', '.join(changed)}")
    return {**table, **options, "parts": entries}


def assemble_file(path, parts: dict | None = None, **options) -> PartsPlant:
    """The plant of :func:`rig_plant_table` (options over the rig file's, as a world's or
    ``--param``'s, ``<part>.<option>`` too): for benchmarks and plant tests, without the harness."""
    return assemble(rig_plant_table(path, parts, **options))
