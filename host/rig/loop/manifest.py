"""A run's manifest (``manifest.json`` in its trace folder, docs/traces.md): everything
that made the result, each piece by hash or version.

- ``firmware``: every file the firmware can import or read (:meth:`Firmware.files`: the
  entry file wherever it lives, the firmware's folders, the board's pin map and drivers),
  each by its place on the board's flash (the per-run copy it ran from, host/rig/targets/boardfs.py),
  its source and its SHA-256, and their digest as the trace header has it;
- ``interpreter``: MicroPython's version, the build variant (``standard``, or ``settrace``
  under coverage), the make options of our build (None for a ``$MICROPYTHON`` of one's own)
  and the binary's SHA-256;
- ``shim``: the SHA-256 of each file of ``host/shim`` and of them all;
- ``plant``: its class, options and, for a robot built of parts, the body and each part
  (and a floor drawn as a picture, by the hash of its grey levels);
- ``run``: app, rig file, board, seed, mode, world, faults (the rig file's and the run's);
- ``harness``: its version and commit (a checkout's; ``unknown`` when installed);
- ``project``: the user's repository the rig file is in (its root and commit), apart from
  the harness's; None for our own apps; ``tools``: Python and each pinned package's version.

The trace header (``header.json``, ``trace.jsonl``) keeps its own short record (commit,
firmware digest, MicroPython version); the manifest holds the rest, and ``header.json``
seals it with the folder's other files (``files``: its SHA-256). :func:`differences` says, one line each, what differs
between two manifests: ``mpy-fil replay`` checks a recording's before it runs.
"""

import functools
import hashlib
import json
import platform
import re
import subprocess
from pathlib import Path

from host.artefacts import integrity
from host.artefacts.folder import MANIFEST
from host.core import interpreter, paths, provenance
from host.core.errors import SetupError
from host.rig.loop.spec import fault_schedule
from host.rig.targets import sandbox
from host.rig.targets.boardfs import on_board

FILE = MANIFEST
VERSION = 1
IGNORED = ("interpreter.path", "harness.commit_time")  # (where a checkout lives is not what ran)
IGNORED += tuple(f"sandbox.{key}" for key in ("setting", "running", "why", "received"))  # (how it was confined)
IGNORED_SECTIONS = ("project",)  # (the user's commit: the firmware's files are hashed one by one)


def _sha256(path: Path) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


@functools.cache
def _binary_sha256(path: str, mtime_ns: int, size: int) -> str:
    return _sha256(Path(path))


@functools.cache
def _binary_version(path: str, mtime_ns: int) -> str:
    try:
        return interpreter.version(Path(path))
    except (OSError, subprocess.SubprocessError) as e:
        return f"unknown ({e})"


def firmware_part(firmware, flashed: dict | None = None) -> dict:
    """The firmware's files: board path -> its source and SHA-256 (the flashed copy's when
    the run has one), and the digest the trace header names."""
    files = {}
    for name, path in on_board(firmware).items():  # (what make flash puts on the board)
        digest = (flashed or {}).get(name) or _sha256(path)
        files[name] = {"source": paths.portable(path), "sha256": digest}
    identity = firmware.identity()
    return {"entry": firmware.entry, "sha256": identity["sha256"], "files": files}


def interpreter_part(variant: str, version: str | None = None) -> dict:
    """The interpreter a run uses: the version asked for, path, its version line, variant,
    make options, binary's SHA-256."""
    asked = interpreter.release(version).version
    try:
        path = interpreter.find_variant(variant, version)
    except SetupError as e:
        return {"micropython": asked, "variant": variant, "error": str(e)}
    stat = path.stat()
    ours = path.resolve() in {interpreter.variant_path(variant, root, version).resolve() for root in _roots()}
    return {
        "micropython": asked,
        "path": str(path),
        "version": _binary_version(str(path), stat.st_mtime_ns),
        "variant": variant,
        "make_options": list(interpreter.make_options(variant, version)) if ours else None,
        "sha256": _binary_sha256(str(path), stat.st_mtime_ns, stat.st_size),
    }


def _roots() -> list[Path]:
    return [interpreter.build_root(), interpreter.build_root(checkout=False)]


def shim_part() -> dict:
    """Each file of the shim (host/shim, its subfolders too) by SHA-256, and their digest."""
    files = {}
    for path in sorted(paths.SHIM_DIR.rglob("*")):
        if path.is_file() and "__pycache__" not in path.parts and path.suffix not in (".pyc", ".o"):
            files[path.relative_to(paths.SHIM_DIR).as_posix()] = _sha256(path)
    whole = hashlib.sha256("".join(f"{k}\0{v}\n" for k, v in files.items()).encode()).hexdigest()
    return {"sha256": whole, "files": files}


def plant_part(plant, options: dict) -> dict:
    """The plant's class and options, and its body and parts as the trace header has them."""
    part = {"class": type(plant.unwrapped).__name__, "options": _plain(options)}
    part.update(_plain(plant.describe() or {}))
    floor = plant.world.floor if plant.world is not None else None
    if floor is not None:  # (a line course's picture: what its line sensors saw, by hash)
        size = [floor.width, floor.height]
        part["floor"] = {"sha256": hashlib.sha256(floor.gray).hexdigest(), "size_px": size, "m_per_px": floor.m_per_px}
    return part


@functools.cache
def tools_part() -> dict:
    """Python and the versions of the packages the harness pins (its requirements)."""
    from importlib import metadata  # (only when a manifest is written)

    found = {"python": platform.python_version()}
    try:
        wanted = metadata.requires("mpy-fil") or []
    except metadata.PackageNotFoundError:
        wanted = []
    for requirement in wanted:
        name = re.split(r"[ ;<>=!~\[]", requirement, maxsplit=1)[0]
        try:
            found[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            continue  # (an extra's package that is not installed)
    return found


def harness_part() -> dict:
    from importlib import metadata

    try:
        version = metadata.version("mpy-fil")
    except metadata.PackageNotFoundError:
        version = "0+unknown"
    return {"version": version, "commit": provenance.commit()}


def project_part(app) -> dict | None:
    """The user's repository the rig file is in, apart from the harness's: its root and
    commit (None for our own apps, or a rig file in no repository)."""
    if app.rig_file is None:
        return None
    return provenance.project_commit(Path(app.rig_file).resolve().parent)


def _plain(value):
    """JSON's types only (tuples as lists, paths and other objects as text)."""
    return json.loads(json.dumps(value, default=str))


def build(app, spec, firmware, plant, plant_options: dict, *, variant="standard", flashed=None) -> dict:
    """The manifest of a run of ``spec`` (its ``app``) with ``firmware`` on ``plant``."""
    header = spec.header(app)
    faults = [{"kind": f.kind, **f.fields} for f in fault_schedule(spec, app)]
    return {
        "manifest": VERSION,
        "run": {
            "app": app.name,
            "rig_file": paths.portable(app.rig_file) if app.rig_file else None,
            "board": header["board"],
            "world": header["world"],
            "seed": spec.seed,
            "mode": spec.mode,
            "faults": _plain(faults),
            "placement": _plain(header["placement"]),
        },
        "firmware": firmware_part(firmware, flashed),
        "interpreter": interpreter_part(variant, firmware.micropython() if hasattr(firmware, "micropython") else None),
        "shim": shim_part(),
        "plant": plant_part(plant, plant_options),
        "harness": harness_part(),
        "project": project_part(app),
        "tools": tools_part(),
    }


def of_rig(rig, plant=None) -> dict:
    """The manifest of a rig (before or after it starts); ``plant``: the one to describe
    instead of the rig's (a replay describes the recorded plant, not its script)."""
    options = dict(rig.plant_options)
    variant = "settrace" if getattr(rig, "coverage_file", None) is not None else "standard"
    flashed = rig.board_fs.flashed if getattr(rig, "board_fs", None) is not None else None
    found = build(rig.app, rig.spec, rig.firmware, plant or rig.plant, options, variant=variant, flashed=flashed)
    found["sandbox"] = sandbox.record(rig.firmware.board_root)  # how it ran, not what ran: IGNORED
    return found


def write(folder: Path, manifest: dict) -> Path | None:
    """``manifest.json`` in ``folder``, whole or not at all: a disk that refuses it leaves
    none (the run goes on; a replay of its folder says it was not checked)."""
    path = Path(folder) / FILE
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        integrity.write_text(path, json.dumps(manifest, indent=1, sort_keys=True) + "\n")
    except (OSError, integrity.TraceWriteError):
        return None
    return path


def read(folder: Path) -> dict | None:
    """A trace folder's manifest, or None when it has none (a folder written before them)."""
    path = Path(folder) / FILE
    if not path.is_file():
        return None
    try:
        found = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError, RecursionError):
        return {"error": f"{path} is not readable JSON"}
    return found if isinstance(found, dict) else {"error": f"{path} is not a JSON object"}


def digest(folder: Path) -> str | None:
    path = Path(folder) / FILE
    return _sha256(path) if path.is_file() else None


def _flat(value, prefix="") -> dict:
    if isinstance(value, dict) and value:
        out = {}
        for key, item in value.items():
            out.update(_flat(item, f"{prefix}.{key}" if prefix else str(key)))
        return out
    return {prefix: value}


def _short(value) -> str:
    text = json.dumps(value, sort_keys=True) if not isinstance(value, str) else value
    if re.fullmatch(r"[0-9a-f]{64}", text):
        return text[:12]
    return text if len(text) <= 80 else text[:77] + "..."


def differences(recorded: dict, now: dict) -> list[str]:
    """What differs between a recorded manifest and the current one, a line each (a
    firmware file by its board path, a tool by name), in a stable order."""
    if "error" in recorded:
        return [f"the recorded manifest: {recorded['error']}"]
    a, b = _flat(recorded), _flat(now)
    changed = [
        k
        for k in sorted(set(a) | set(b))
        if k not in IGNORED and k.split(".", 1)[0] not in IGNORED_SECTIONS and a.get(k, _MISSING) != b.get(k, _MISSING)
    ]
    lines = []
    for key in changed:
        section = key.split(".", 1)[0]
        if key.startswith("firmware.files.") and key.endswith(".source"):
            continue  # (where the source lies: its hash says whether it is the same)
        if key == f"{section}.sha256" and any(k.startswith(f"{section}.files.") for k in changed):
            continue  # (the digest of files named one by one)
        lines.append(_line(key, a.get(key, _MISSING), b.get(key, _MISSING)))
    return lines


_MISSING = object()


def _line(key: str, was, now) -> str:
    if key.startswith("firmware.files.") and key.endswith(".sha256"):
        key = f"firmware file {key[len('firmware.files.') : -len('.sha256')]}"
    elif key.startswith("shim.files."):
        key = f"shim file {key[len('shim.files.') :]}"
    if was is _MISSING:
        return f"{key}: not in the recording, now {_short(now)}"
    if now is _MISSING:
        return f"{key}: was {_short(was)}, now none"
    return f"{key}: was {_short(was)}, now {_short(now)}"


def of_campaign(rig: str, campaign: dict) -> dict:
    """A campaign's manifest: what its runs share (the rig's firmware, the interpreter, the
    shim, the plant of its first world, harness and tools) and the campaign itself (its
    seeds, worlds and fault sets: each run's seed and faults are in results.jsonl)."""
    from host.rig.config.boardfile import load_boards, names_boards
    from host.rig.loop.spec import RigSpec, build_plant
    from host.rig.targets.firmware import Firmware

    if str(rig).endswith(".toml") and names_boards(rig):  # a set of boards: each board's, the first's in full
        made = {name: of_campaign(f"{rig}::{name}", campaign) for name in load_boards(rig).firmware()}
        found = next(iter(made.values()))
        found["boards"] = {name: each.get("firmware") for name, each in made.items()}
        return found
    spec = RigSpec(rig, world=(campaign.get("worlds") or [None])[0])
    app = spec.resolve()
    board_folder, _pins = app.board_files(spec.board or app.default_board)
    plant, options = build_plant(spec, app)
    found = build(app, spec, Firmware.from_app(app, board_folder), plant, dict(options))
    found["run"] = {**found["run"], "seed": None, "campaign": _plain(campaign)}
    return found


def write_campaign(out: Path, rig: str, campaign: dict) -> Path | None:
    """``manifest.json`` in a campaign's folder, as its first run starts (a campaign that
    resumes keeps the one it began with)."""
    if (Path(out) / FILE).is_file():
        return None
    return write(out, of_campaign(rig, campaign))
