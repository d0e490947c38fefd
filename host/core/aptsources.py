"""The Debian archive this machine's apt already uses, for fetching MicroPython's source.

The interpreter build (:mod:`host.core.interpreter`) fetches one pinned source package
with ``apt-get source`` through a project-local apt configuration. Which mirror to fetch
from is the machine's business, not the project's: a developer behind a local mirror, a CI
image with its own, a machine pinned to a snapshot all say it in their apt sources. This
module reads them (the one-line ``.list`` format and deb822 ``.sources`` files, where
``apt-config`` says they are) and picks the first enabled entry of Debian's main archive;
``DEBIAN_MIRROR=URI`` overrides it. The repository names no mirror host.
"""

import os
import re
import subprocess
from dataclasses import dataclass, field
from pathlib import Path

from host.core.errors import SetupError

CODENAMES = {
    "buster",
    "bullseye",
    "bookworm",
    "trixie",
    "forky",
    "duke",
    "sid",
    "stable",
    "testing",
    "unstable",
    "oldstable",
    "oldoldstable",
}
"""Suites of Debian's main archive (a suite with a suffix, such as ``-security`` or
``-updates``, lives in another archive or only carries changes)."""

OVERRIDE = "DEBIAN_MIRROR"


@dataclass(frozen=True)
class Entry:
    """One apt source: where it came from, its URI, suites, components and options."""

    origin: str
    types: tuple[str, ...]
    uri: str
    suites: tuple[str, ...]
    components: tuple[str, ...]
    options: dict = field(default_factory=dict, compare=False)

    def is_debian_main_archive(self) -> bool:
        return (
            any(t in ("deb", "deb-src") for t in self.types)
            and "main" in self.components
            and any(s in CODENAMES for s in self.suites)
            and not self.uri.startswith(("cdrom:", "copy:"))
        )


def source_files() -> list[Path]:
    """The machine's apt source files, where its apt configuration puts them."""
    try:
        out = subprocess.run(
            ["apt-config", "shell", "L", "Dir::Etc::SourceList/f", "P", "Dir::Etc::SourceParts/d"],
            capture_output=True,
            text=True,
            timeout=10,
            check=True,
        ).stdout
        found = dict(re.findall(r"^(\w)='(.*)'$", out, re.M))
    except (OSError, subprocess.SubprocessError):
        found = {}
    main = Path(found.get("L", "/etc/apt/sources.list"))
    parts = Path(found.get("P", "/etc/apt/sources.list.d"))
    files = [main] if main.is_file() else []
    if parts.is_dir():
        files += sorted(p for p in parts.iterdir() if p.suffix in (".list", ".sources") and p.is_file())
    return files


def parse_one_line(text: str, origin: str) -> list[Entry]:
    """``deb [opt=value ...] URI suite component...`` lines."""
    entries = []
    for number, raw in enumerate(text.splitlines(), 1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        options = {}
        match = re.match(r"^(deb(?:-src)?)\s+(?:\[([^\]]*)\]\s+)?(\S+)\s+(\S+)\s*(.*)$", line)
        if not match:
            continue
        kind, opts, uri, suite, comps = match.groups()
        for item in (opts or "").split():
            key, _, value = item.partition("=")
            options[key.lower()] = value
        entries.append(Entry(f"{origin}:{number}", (kind,), uri, (suite,), tuple(comps.split()), options))
    return entries


def parse_deb822(text: str, origin: str) -> list[Entry]:
    """Stanzas of ``Types:``, ``URIs:``, ``Suites:``, ``Components:`` (``Enabled: no``
    stanzas skipped)."""
    entries = []
    for number, stanza in enumerate(re.split(r"\n\s*\n", text), 1):
        fields: dict[str, str] = {}
        key = None
        for raw in stanza.splitlines():
            if raw.lstrip().startswith("#") or not raw.strip():
                continue
            if raw[:1].isspace() and key:
                fields[key] += " " + raw.strip()
                continue
            key, _, value = raw.partition(":")
            key = key.strip().lower()
            fields[key] = value.strip()
        if fields.get("enabled", "yes").lower() == "no" or "uris" not in fields:
            continue
        options = {k: v for k, v in fields.items() if k not in ("types", "uris", "suites", "components")}
        for uri in fields["uris"].split():
            entries.append(
                Entry(
                    f"{origin} stanza {number}",
                    tuple(fields.get("types", "").split()),
                    uri,
                    tuple(fields.get("suites", "").split()),
                    tuple(fields.get("components", "").split()),
                    options,
                )
            )
    return entries


def entries(files: list[Path] | None = None) -> list[Entry]:
    found = []
    for path in source_files() if files is None else files:
        try:
            text = path.read_text(encoding="utf-8", errors="replace")
        except OSError:
            continue
        parse = parse_deb822 if path.suffix == ".sources" else parse_one_line
        found += parse(text, str(path))
    return found


def debian_mirror(files: list[Path] | None = None) -> str:
    """The URI of Debian's main archive as this machine's apt has it (``$DEBIAN_MIRROR``
    first). Raises :class:`SetupError` naming the files read when there is none."""
    override = os.environ.get(OVERRIDE, "").strip()
    if override:
        return override.rstrip("/")
    files = source_files() if files is None else files
    for entry in entries(files):
        if entry.is_debian_main_archive():
            return entry.uri.rstrip("/")
    read = ", ".join(map(str, files)) or "none found"
    raise SetupError(
        "no Debian archive (a 'main' component of a Debian suite) in this machine's apt sources "
        f"(read: {read}); set {OVERRIDE}=<the URI of a Debian mirror> to fetch MicroPython's source from it"
    )
