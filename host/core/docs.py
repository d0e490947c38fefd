"""The project's documentation, as the installed package carries it: ``mpy-fil docs [TOPIC]``.

Every ``docs/NAME.md`` that ``--help``, an error message or another page names is a topic
``NAME`` here (``docs/NAME.md`` and ``NAME.md`` are taken too), and ``readme`` is the
README. In a checkout they are the repository's ``docs/`` folder and ``README.md``; the
wheel carries ``docs/*.md`` as package data under ``host/_data/docs`` (setup.py) and the
README as the package's description (pyproject.toml's ``readme``).

    mpy-fil docs                      every topic with its title
    mpy-fil docs ci                   the page, whole (through a pager on a terminal)
    mpy-fil docs rig-file "Budgets"   one section of it (a heading, or the start of one)
    mpy-fil docs ci --path            where the file is (to open it in an editor or a browser)

A topic or section that does not exist is refused with the nearest names and the list.
"""

import difflib
import re
import sys
from pathlib import Path

from host.core import paths
from host.core.errors import ConfigError

DOCS = paths.REPO / "docs" if paths.CHECKOUT else paths.BUNDLED / "docs"
"""The folder of the ``.md`` pages (a checkout's ``docs/``, the wheel's ``host/_data/docs``)."""
README = "readme"
REFERENCE = re.compile(r"\bdocs/([A-Za-z0-9_.-]+?)\.md\b")
"""How a message or a page names a page: ``docs/NAME.md``."""
HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")
FENCE = re.compile(r"^\s*(```|~~~)")


def topics() -> dict[str, Path | None]:
    """Every topic by name, sorted, with its file (None: the README from the package's
    metadata, which has no file of its own)."""
    found: dict[str, Path | None] = {p.stem: p for p in DOCS.glob("*.md") if p.is_file()}
    readme = paths.REPO / "README.md"
    found[README] = readme if paths.CHECKOUT and readme.is_file() else None
    return dict(sorted(found.items()))


def text_of(name: str) -> str:
    """A topic's whole text."""
    path = topics().get(name, Path())
    if path is not None:
        return path.read_text(encoding="utf-8")
    from importlib.metadata import PackageNotFoundError, metadata

    try:
        return metadata("mpy-fil").get_payload() or metadata("mpy-fil").get("Description", "")
    except PackageNotFoundError:
        return ""


def title(name: str) -> str:
    """A topic's first line, its heading's text."""
    for line in text_of(name).splitlines():
        if line.strip():
            return line.lstrip("#").strip()
    return ""


def topic_name(given: str) -> str:
    """The topic ``given`` names (``ci``, ``ci.md``, ``docs/ci.md``, any case); a
    :class:`ConfigError` with the nearest names and every name when there is none."""
    name = given.strip().replace("\\", "/").removeprefix("./").removeprefix("docs/").removesuffix(".md")
    known = topics()
    for candidate in (name, name.lower()):
        if candidate in known:
            return candidate
    if name.lower() in ("readme", "readme.md"):
        return README
    near = difflib.get_close_matches(name.lower(), list(known), n=3, cutoff=0.5)
    hint = f"; did you mean {' or '.join(near)}?" if near else ""
    raise ConfigError(f"TOPIC: no page {given!r}{hint} (topics: {', '.join(known)}; `mpy-fil docs` lists them)")


def section(name: str, heading: str) -> str:
    """The section of topic ``name`` under ``heading`` (its whole heading, or the start of
    one, any case), to the next heading of its level or above; a :class:`ConfigError`
    naming the nearest headings when none matches."""
    lines = text_of(name).splitlines()
    found = _headings(lines)
    wanted = _plain(heading)
    for match in (lambda h: h == wanted, lambda h: h.startswith(wanted), lambda h: wanted in h):
        hits = [(i, level) for i, level, text in found if match(_plain(text))]
        if hits:
            start, level = hits[0]
            end = next((i for i, lv, _ in found if i > start and lv <= level), len(lines))
            return "\n".join(lines[start:end]).rstrip() + "\n"
    texts = [text for _, _, text in found]
    near = difflib.get_close_matches(heading, texts, n=3, cutoff=0.4)
    hint = f"; did you mean {' or '.join(repr(n) for n in near)}?" if near else ""
    raise ConfigError(f"SECTION: no heading {heading!r} in {name}{hint} (its headings: {'; '.join(texts) or 'none'})")


def _headings(lines: list[str]) -> list[tuple[int, int, str]]:
    """(line index, level, text) of each heading outside code blocks."""
    found, fenced = [], False
    for i, line in enumerate(lines):
        if FENCE.match(line):
            fenced = not fenced
            continue
        heading = None if fenced else HEADING.match(line)
        if heading:
            found.append((i, len(heading.group(1)), heading.group(2)))
    return found


def _plain(text: str) -> str:
    return re.sub(r"[`*_\"]", "", text).strip().lower()


def listing() -> str:
    """Every topic with its title, and how to read one."""
    names = topics()
    width = max(map(len, names))
    rows = [f"  {name:<{width}}  {title(name)}" for name in names]
    return "\n".join(["topics (mpy-fil docs TOPIC; docs/NAME.md in a message is topic NAME):", *rows])


def add_parser(sub) -> None:
    """The ``docs`` subcommand (``host/cli.py`` calls this)."""
    docs = sub.add_parser("docs", help="print a page of the documentation (docs/NAME.md is topic NAME); list them")
    docs.add_argument("topic", nargs="?", metavar="TOPIC", help="a page: ci, rig-file, rig-api, ...; none: the list")
    docs.add_argument("section", nargs="?", metavar="SECTION", help="only the section under this heading")
    docs.add_argument("--path", action="store_true", help="print where the page (or the docs folder) is, not its text")
    docs.set_defaults(command=lambda args: docs_command(args, say=print), sub=docs)


def docs_command(args, say) -> int:
    """``mpy-fil docs``: the list, a page (paged on a terminal), a section, or a path."""
    if args.topic is None:
        if args.section is not None:  # (argparse fills TOPIC first: unreachable, kept for callers)
            raise ConfigError("SECTION: a section needs its TOPIC")
        say(str(DOCS) if args.path else listing())
        return 0
    name = topic_name(args.topic)
    if args.path:
        path = topics()[name]
        if path is None:
            raise ConfigError(f"--path: the installed package carries {name} as its description, not as a file")
        say(str(path))
        return 0
    text = text_of(name) if args.section is None else section(name, args.section)
    if sys.stdout.isatty() and args.section is None:
        import pydoc

        pydoc.pager(text)
    else:
        say(text.rstrip("\n"))
    return 0
