"""Replay a trace: drive the firmware with the recorded sensor stream and compare what it
drives with what it drove.

The plant is a :class:`ReplayPlant`, a :class:`sim_plant.scripted.ScriptedPlant` whose
script is every recorded plant-output change, in recorded order. The firmware runs in
lockstep for the recorded length; its outputs (actuators, probes, bare pins) are
compared one by one with the recorded ones and the first difference is reported. The
same firmware on the same recording gives none: a difference means the firmware, the
shim or the rig changed behaviour (or the trace was taken in real time, which no
replay reproduces).

A replay never runs past what was recorded: the header's ``t_end_us`` must lie within the
recording (no earlier than its last change, no later than a truth period past its last
truth row). A partial recording (a run stopped by a signal, docs/traces.md) is replayed to
its cut, and only what happened before the cut's instant is compared: the cut may fall
between two outputs of one instant. The cut's instant is the header's ``stop`` ``t_us``,
where the firmware was (the STATE it ran from), which may lie before ``t_end_us``, where
the plant was (a lookahead past that STATE).

A trace folder is data: a replay never runs a firmware the user did not name
(docs/security.md). It runs the firmware given by :class:`FirmwareChoice` (``--app``, a
rig file or one of our apps; ``--firmware``, a firmware folder), or one of our own apps
that the header names by name (code the harness ships); a rig file or firmware folder the
header names runs only with ``trust_folder`` (``--trust-folder``). The result says which ran.

Before it runs, a replay checks the recording's ``manifest.json`` (host/rig/loop/manifest.py)
against the run it is about to make: each difference (a firmware file, the interpreter's
binary, the shim, a tool's version, the plant's parts...) is one line, and a difference
stops the replay (:class:`ManifestMismatch`) unless ``ignore_manifest``
(``--ignore-manifest``); the firmware's own differences do not stop it when the user named
the firmware (``--app``, ``--firmware``: that is the point; they are still listed).
``--trust-folder`` runs the firmware the header names, which must still be what was
recorded. A folder without a manifest
(written before them) is replayed as before, and the result says it was not checked.
"""

import json
from dataclasses import dataclass
from pathlib import Path

from host.artefacts.checks import partial_reason
from host.artefacts.folder import LINK, TraceData, load_trace
from host.artefacts.recorder import ROLE_ACTUATOR, ROLE_SENSOR, SENT
from host.core import safefs
from host.core.errors import ConfigError, HarnessError
from host.link import frames as F
from host.rig.loop import manifest
from host.rig.loop.rig import Rig
from host.rig.loop.spec import PlantOptionsError, Recording, RigSpec, build_plant
from sim_plant.plant import BUSES, UART
from sim_plant.scripted import ScriptedPlant


class ReplayPlant(ScriptedPlant):
    """A ScriptedPlant that keeps the recorded order of same-time changes and can be
    snapshotted cheaply (the rig rolls speculative batches back)."""

    capabilities = frozenset((BUSES, UART))  # (the recorded bus reads, answered in order; UART bytes sent)

    def __init__(self, script, *, outputs, inputs, initial):
        super().__init__((), outputs=outputs, inputs=inputs, initial=initial)
        unknown = sorted({name for _t, name, _v in script} - set(outputs))
        if unknown:
            raise ConfigError(f"replay: the recording drives unknown plant outputs {unknown}")
        self.script = sorted(script, key=lambda e: e[0])  # stable: same-time order as recorded
        self.transfers: dict[str, list] = {}  # bus -> its recorded transfers, in order
        self.answered: dict[str, int] = {}  # bus -> how many of them were answered

    def bus_transfer(self, bus: str, op: int, address: int, n_read: int, data: bytes, unclocked=frozenset()) -> tuple:
        """The recorded reply to the bus's next transfer (status, count, bytes read); a
        transfer the recording does not have (another op or address, or one more) is
        answered as by no device: the replay has diverged, and says so by its outputs."""
        done = self.answered.get(bus, 0)
        recorded = self.transfers.get(bus, [])
        if done >= len(recorded) or recorded[done][:2] != (op, address):
            return (F.BUS_NACK_ADDRESS, 0, b"") if op in (F.BUS_XFER, F.BUS_XFER_NOSTOP) else (F.BUS_OK, 0, b"")
        self.answered[bus] = done + 1
        return recorded[done][2]

    def send_bytes(self, name: str, data: bytes, baud: int) -> None:
        """Bytes a UART sends on a line the recording's plant timed (a board_uart, a
        record link): an output of the firmware's, compared as any other (on a line the
        firmware reads too, as the recorder named it: ``<signal>:sent``)."""
        self.set_input(name + SENT if name in self.outputs else name, bytes(data))

    def snapshot(self):
        return self._t_us, self._next, dict(self.values), len(self.log), dict(self.answered)

    def restore(self, snap) -> None:
        self._t_us, self._next, values, n_log, answered = snap
        self.values = dict(values)
        del self.log[n_log:]
        self.answered = dict(answered)


@dataclass
class Difference:
    index: int  # position in the firmware's output stream
    t_us: int
    recorded: tuple | None  # (t_us, signal, value), None past the recording's end
    replayed: tuple | None

    def __str__(self) -> str:
        def show(e):
            return "nothing" if e is None else f"{e[1]} = {e[2]} at t={e[0] / 1e6:.6f} s"

        return (
            f"first difference at output #{self.index} (t={self.t_us / 1e6:.6f} s): "
            f"recorded {show(self.recorded)}, replay {show(self.replayed)}"
        )


@dataclass
class ReplayResult:
    recorded: int  # firmware outputs in the recording
    replayed: int  # firmware outputs in the replay
    difference: Difference | None
    folder: Path  # the replay's own trace folder
    partial: str | None = None  # why the recording is partial: compared up to its cut
    firmware: str = ""  # which firmware ran, and who named it
    manifest: list[str] | None = None  # what differs from the recording's manifest (None: it has none)

    @property
    def same(self) -> bool:
        return self.difference is None


class ManifestMismatch(HarnessError):
    """The run a replay would make differs from the one recorded (its manifest.json)."""

    def __init__(self, folder, lines: list[str]):
        self.lines = lines
        listed = "\n".join(f"  {line}" for line in lines)
        super().__init__(
            f"trace {folder}: this replay would not run what made the recording; manifest.json differs "
            f"in {len(lines)} place(s):\n{listed}\nreplay it anyway with --ignore-manifest"
        )


TOLD_ONLY = ("harness.", "tools.")
"""Differences a replay names and goes on with: a newer harness or tool replaying an older
recording is what a regression check does; the firmware, the interpreter, the shim and the
plant it ran against stop it (docs/traces.md)."""


def check_manifest(folder: Path, rig: Rig, plant, choice: "FirmwareChoice", ignore: bool) -> list[str] | None:
    """What differs between the recording's manifest and this replay's run (``plant``: the
    recorded one, as the manifest describes it), one line each; None without a manifest.
    Raises ManifestMismatch on a difference the user did not choose, unless ``ignore``."""
    recorded = manifest.read(folder)
    if recorded is None:
        return None
    lines = manifest.differences(recorded, manifest.of_rig(rig, plant=plant))
    chosen = ("firmware", "firmware file", "run.app", "run.rig_file")
    named = choice.app is not None or choice.firmware is not None
    stopping = [line for line in lines if not (named and line.startswith(chosen)) and not line.startswith(TOLD_ONLY)]
    if stopping and not ignore:
        raise ManifestMismatch(folder, lines)
    return lines


@dataclass(frozen=True)
class FirmwareChoice:
    """The firmware a replay runs: ``app`` (a rig file or one of our apps) and/or
    ``firmware`` (a firmware folder, the board's /) as the user names them; ``trust_folder``:
    run the rig file or folder the trace's header names."""

    app: str | None = None
    firmware: Path | None = None
    trust_folder: bool = False


FOLDER_FIRMWARE_FIELDS = ("main_dir", "firmware_dir")  # a header's spec fields that name code to run


def chosen_spec(header: dict, choice: FirmwareChoice, **changes) -> tuple[RigSpec, str]:
    """The spec a replay runs and a sentence saying which firmware and who named it; a
    ConfigError when the header alone names code from outside the harness (a rig file, a
    firmware folder) and the user did not name one nor pass ``trust_folder``."""
    spec = RigSpec.from_header(header, **changes)
    named = [f"{f} {getattr(spec, f)}" for f in FOLDER_FIRMWARE_FIELDS if getattr(spec, f)]
    if choice.app is not None:
        spec = spec.replace(app=choice.app)
    elif not _ours(spec.app):
        named.append(f"the rig file {spec.app}")
    if choice.firmware is not None:
        spec = spec.replace(main_dir=Path(choice.firmware), firmware_dir=None)
        named = [n for n in named if not n.startswith(FOLDER_FIRMWARE_FIELDS)]
    if named and not choice.trust_folder:
        raise ConfigError(
            f"the trace folder's header names a firmware to run ({'; '.join(named)}): a replay runs only "
            "a firmware you name: --app RIG (a rig file or one of our apps), --firmware DIR (a firmware "
            "folder), or --trust-folder to run the one the header names"
        )
    return spec, _which(spec, choice, bool(named))


def _ours(app) -> bool:
    """One of the apps the harness ships, named by its name (not a path)."""
    from host.rig.config.apps import apps

    return isinstance(app, str) and app in apps()


def _which(spec: RigSpec, choice: FirmwareChoice, from_folder: bool) -> str:
    folder = spec.firmware_dir or spec.main_dir
    app = spec.resolve()
    where = folder or app.path
    if choice.firmware is not None:
        who = "named by --firmware"
    elif choice.app is not None:
        who = "named by --app"
    elif from_folder:
        who = "named by the trace folder's header, run because of --trust-folder"
    else:
        who = f"our app {app.name}, named by the trace folder's header"
    return f"{where} ({who})"


def replay_plant(trace: TraceData) -> ReplayPlant:
    h = trace.header
    signals = h.get("signals", {})
    outputs = {n: i["kind"] for n, i in signals.items() if i["role"] == ROLE_SENSOR}
    inputs = {n: i["kind"] for n, i in signals.items() if i["role"] == ROLE_ACTUATOR}
    inputs |= {n.removesuffix(SENT): k for n, k in inputs.items() if n.endswith(SENT)}  # (the two-way lines)
    try:
        script = [(t, n, bytes.fromhex(v) if outputs[n] == "bytes" else v) for t, n, v in trace.events if n in outputs]
        initial = {n: (bytes.fromhex(v) if outputs.get(n) == "bytes" else v) for n, v in h.get("initial", {}).items()}
    except (ValueError, TypeError) as e:
        raise ConfigError(f"trace {trace.folder}: a recorded byte value is not hex text ({e})") from None
    plant = ReplayPlant(script, outputs=outputs, inputs=inputs, initial=initial)
    plant.transfers = recorded_transfers(trace.folder / LINK)
    return plant


def recorded_transfers(link_log: Path) -> dict[str, list]:
    """Each bus's transfers in the link log, in order: (op, address, (status, count, read))."""
    transfers: dict[str, list] = {}
    if not link_log.is_file():
        return transfers
    with open(link_log, "rb") as lines:
        for raw in lines:
            if b'"BUS"' not in raw:
                continue
            line = raw.decode("utf-8", "replace")
            try:
                r = json.loads(raw)
                if r.get("msg") == "BUS" and "bus" in r:
                    reply = (r["status"], r.get("count", len(bytes.fromhex(r["read"]))), bytes.fromhex(r["read"]))
                    transfers.setdefault(r["bus"], []).append((r["op"], r["address"], reply))
            except (ValueError, KeyError, TypeError, RecursionError) as e:
                raise ConfigError(f"{link_log}: a BUS record is damaged ({e}): {line[:120]}") from None
    return transfers


def recorded_end_us(trace: TraceData) -> int:
    """The header's ``t_end_us``, checked against what was recorded."""
    h = trace.header
    t_end_us = h["t_end_us"]
    last_event_us = max((e[0] for e in trace.events), default=0)
    t_truth = trace.truth.get("t_us")
    last_truth_us = int(t_truth[-1]) if t_truth is not None and len(t_truth) else 0
    limit_us = last_truth_us + h.get("truth_period_us", 50_000)
    if not last_event_us <= t_end_us <= limit_us:
        raise ConfigError(
            f"trace {trace.folder}: header.json t_end_us {t_end_us} is outside what was recorded "
            f"(changes up to {last_event_us}, truth up to {last_truth_us}); the header does not belong to these files"
        )
    return t_end_us


def replay(
    folder,
    artefacts,
    *,
    watchdog_s: float = 5.0,
    progress=None,
    busy_poll: bool = True,
    choice: FirmwareChoice = FirmwareChoice(),
    say=None,
    ignore_manifest: bool = False,
) -> ReplayResult:
    """Run the recorded spec (app, board, seed, ...) against the recorded sensor stream;
    compare. ``busy_poll``: this process may spin on its link (the front end's choice);
    ``choice``: the firmware the user named (a trace folder's own runs only when trusted);
    ``say(text)`` is told which firmware runs, before it starts; ``ignore_manifest``: run
    despite differences from the recording's manifest (:func:`check_manifest`)."""
    label = "the trace folder replayed"
    safefs.output_folder(artefacts, what="replay's trace folder", inputs={label: folder}, owned={label: "replay"})
    trace = load_trace(folder)
    h = trace.header
    if h.get("mode") != "lockstep":
        raise ConfigError(f"trace {folder}: recorded in {h.get('mode')} mode; only lockstep runs replay exactly")
    t_end_us = recorded_end_us(trace)
    partial = partial_reason(h)
    try:
        spec, which = chosen_spec(trace.header, choice, watchdog_s=watchdog_s, busy_poll=busy_poll)
        rig, recorded_plant = _replay_rig(trace, spec, Path(artefacts), progress)
    except ConfigError as e:  # (an app, board or option the header names that is not there)
        named = choice.app is not None or choice.firmware is not None
        raise ConfigError(f"trace {folder}: {'the firmware you named' if named else 'header.json'}: {e}") from None
    differs = check_manifest(Path(folder), rig, recorded_plant, choice, ignore_manifest)
    if say is not None:
        say(which)
    with rig:
        rig.run_until(t_end_us)
    stop = h.get("stop") if partial else None
    cut_us = stop["t_us"] if isinstance(stop, dict) and isinstance(stop.get("t_us"), int) else t_end_us
    cut_us = min(cut_us, t_end_us)  # (the firmware's instant at the cut: the plant may have looked ahead)
    before = (lambda t: t < cut_us) if partial else (lambda t: t <= t_end_us)
    recorded = [e for e in trace.firmware_outputs() if before(e[0])]
    replayed = [e for e in rig.recorder.firmware_outputs() if before(e[0])]
    difference = first_difference(recorded, replayed)
    return ReplayResult(len(recorded), len(replayed), difference, Path(artefacts), partial, which, differs)


def _replay_rig(trace: TraceData, spec: RigSpec, artefacts: Path, progress) -> tuple[Rig, object]:
    """The spec, driven by the recording (the budgets as it had them), and the plant the
    recording was made with (its manifest describes that one)."""
    app = spec.resolve()
    try:
        recorded_plant, _ = build_plant(spec, app)
    except PlantOptionsError:  # (a trace of a plant of one's own: the app's defaults)
        recorded_plant, _ = build_plant(RigSpec(app, seed=spec.seed), app)
    recording = Recording(trace=True, record=True, artefacts=artefacts, progress=progress)
    return Rig(spec, recording, plant=replay_plant(trace), budgets=app.make_budgets(recorded_plant)), recorded_plant


def first_difference(recorded: list, replayed: list) -> Difference | None:
    for i, (a, b) in enumerate(zip(recorded, replayed)):
        if tuple(a) != tuple(b):
            return Difference(i, min(a[0], b[0]), tuple(a), tuple(b))
    if len(recorded) == len(replayed):
        return None
    i = min(len(recorded), len(replayed))
    a = tuple(recorded[i]) if i < len(recorded) else None
    b = tuple(replayed[i]) if i < len(replayed) else None
    return Difference(i, (a or b)[0], a, b)
