"""Robot kits as data: ``mpy-fil kits`` lists them, ``mpy-fil init --kit NAME DIR`` writes
one's rig file and a test beside it (docs/kits.md).

A kit is a folder here: ``kit.toml`` (what it is, its board, where each number comes
from), ``rig.toml`` (the rig file written as it is: a rig like any user's) and ``test.py``
(the test written as ``test_<name>.py``: it runs a small firmware of its own against the
rig and holds it to the plant's ground truth). A kit of one's own is the same two files, a
rig and a test, in one's own repository."""

import difflib
from dataclasses import dataclass
from pathlib import Path

from host.core import safefs
from host.core.errors import ConfigError
from host.rig.config.tomlfile import read_toml

KITS_DIR = Path(__file__).parent


@dataclass(frozen=True)
class Kit:
    name: str
    title: str
    board: str  # MicroPython's board definition (ports/rp2/boards/<board>)
    library: str  # the vendor's MicroPython library
    sources: tuple  # (what, where) pairs
    folder: Path

    def files(self) -> dict[str, Path]:
        """What ``init --kit`` writes (the name in the user's folder: the kit's file)."""
        return {"rig.toml": self.folder / "rig.toml", f"test_{self.name}.py": self.folder / "test.py"}


def kits() -> dict[str, Kit]:
    found = {}
    for meta in sorted(KITS_DIR.glob("*/kit.toml")):
        data = read_toml(meta)
        found[meta.parent.name] = Kit(
            meta.parent.name,
            data["title"],
            data["board"],
            data["library"],
            tuple((s["what"], s["where"]) for s in data.get("sources", ())),
            meta.parent,
        )
    return found


def kit(name: str) -> Kit:
    known = kits()
    if name not in known:
        near = _near(name, known)
        hint = f"did you mean {' or '.join(near)}? " if near else ""
        raise ConfigError(f"no kit {name!r} ({hint}kits: {', '.join(known)}; mpy-fil kits lists them)")
    return known[name]


def _near(name: str, known: dict) -> list[str]:
    """The kits a mistyped name means: those whose name or title holds it (``pololu``,
    ``3pi``, ``maker-pi``), else the closest names."""
    typed = name.lower().replace("-", "_").replace(" ", "_")
    held = [k for k, v in known.items() if typed and (typed in k or typed.replace("_", " ") in v.title.lower())]
    return held or difflib.get_close_matches(typed, list(known), n=2, cutoff=0.6)


def write(name: str, folder: Path) -> list[Path]:
    """The kit's rig file and test in ``folder`` (a real folder): none written when one of
    them is there already, and never through a link (host/core/safefs.py)."""
    chosen = kit(name)
    texts = {folder / dest: src.read_text() for dest, src in chosen.files().items()}  # (all read first)
    for path in texts:
        safefs.refuse_link(path, "argument DIR:")
        if path.exists():
            raise FileExistsError(path)
    for path, text in texts.items():
        safefs.write_new(path, text)
    return list(texts)
