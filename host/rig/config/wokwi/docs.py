"""The part table of ``docs/wokwi.md``, generated from :mod:`host.rig.config.wokwi.parts` (a test
keeps the page in step): ``python -m host.rig.config.wokwi.docs`` rewrites it between its markers."""

import sys

from host.core.paths import REPO
from host.rig.config.wokwi.boards import BOARDS
from host.rig.config.wokwi.parts import REFUSED, TABLE

PAGE = REPO / "docs" / "wokwi.md"
BEGIN = "<!-- the part table: python -m host.rig.config.wokwi.docs writes it from host/rig/config/wokwi/parts.py -->"
END = "<!-- end of the part table -->"


def _cell(text: str) -> str:
    return text.replace("|", "\\|")


def render_table() -> str:
    """Boards, mapped parts (attributes, what differs) and refused parts, as Markdown."""
    lines = [BEGIN, "", "| Wokwi board | chip family (`[board] family`) | its pin names |", "|---|---|---|"]
    styles = {"devkit_v1": "`D13`", "number": "`13`", "pico": "`GP15`"}
    for b in BOARDS.values():
        named = ", ".join(f"`{n}` = {g}" for n, g in b.named)
        lines.append(f"| `{b.wokwi}` | `{b.family}` ({b.title}) | {styles[b.style]}{'; ' + named if named else ''} |")
    lines += ["", "| Wokwi part | our part | attributes | what differs |", "|---|---|---|---|"]
    for p in TABLE.values():
        attrs = "; ".join(f"`{a}`: {_cell(what)}" for a, what in p.attrs.items()) or "none"
        if p.cosmetic:
            attrs += "; drawing only: " + ", ".join(f"`{c}`" for c in p.cosmetic)
        kind = p.kind if p.kind.startswith("(") else f"`{p.kind}`"
        lines.append(f"| `{p.wokwi}` | {kind} | {attrs} | {_cell(p.differs)} |")
    lines += ["", "| refused Wokwi part | why |", "|---|---|"]
    lines += [f"| `{t}` | {_cell(why)} |" for t, why in REFUSED.items()]
    return "\n".join([*lines, "", END])


def page_with_table(text: str) -> str:
    """``text`` (the page) with its table between the markers replaced by the generated one."""
    head, rest = text.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    return head + render_table() + tail


def main() -> int:
    PAGE.write_text(page_with_table(PAGE.read_text()))
    print(f"wrote the part table of {PAGE}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
