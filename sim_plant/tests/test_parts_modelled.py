"""What each chip's model does and does not, per chip, in docs/parts.md (issue 41, point 13):
every chip part (a part on a bus, or a strip of LEDs on a pin) declares both in its own
module (``MODELLED_FEATURES``, ``NOT_MODELLED``), and its section of the generated page
shows each declared line and, for a register chip, every register its ``MODELLED`` lists;
``sim_plant/tests/test_catalogue.py`` holds the whole page to the code."""

import re

from sim_plant import catalogue
from sim_plant.catalogue.docs import PAGE

LED_STRIPS = {"ws2812_strip"}  # (on a pin, not a bus: chips all the same)


def chips() -> dict:
    return {k: c for k, c in catalogue.parts().items() if any(o.name == "bus" for o in c.OPTIONS) or k in LED_STRIPS}


def section(page: str, kind: str) -> str:
    start = page.index(f"## Part `{kind}`\n")
    end = page.find("\n## ", start + 1)
    return page[start : end if end >= 0 else len(page)]


def test_every_chip_declares_what_its_model_does_and_does_not():
    found = chips()
    assert {"lsm6dsox", "mpu6050", "ssd1306", "ds18b20", "apa102_strip", "ws2812_strip", "vl53l1x"} <= set(found)
    missing = [k for k, c in found.items() if not c.NOT_MODELLED or not c.MODELLED_FEATURES]
    assert not missing, f"chips with no MODELLED_FEATURES or NOT_MODELLED in their module: {missing}"


def test_each_chips_section_of_docs_parts_shows_its_declarations_and_registers():
    page = PAGE.read_text()
    for kind, cls in chips().items():
        text = section(page, kind)
        rows = {m.group(1): m.group(2) for m in re.finditer(r"^\| (does|does not) \| (.*) \|$", text, re.M)}
        assert set(rows) == {"does", "does not"}, f"{kind}: no modelled / not modelled table in docs/parts.md"
        for line in cls.MODELLED_FEATURES:
            assert line in rows["does"], f"{kind}: {line!r} not in its 'does' row: {rows['does']}"
        for line in cls.NOT_MODELLED:
            assert line in rows["does not"], f"{kind}: {line!r} not in its 'does not' row: {rows['does not']}"
        chip = getattr(cls, "CHIP", None)
        shown = set()
        for first, last in re.findall(r"^\| 0x([0-9a-f]{2})(?:\.\.0x([0-9a-f]{2}))? \|", text, re.M):
            shown.update(range(int(first, 16), int(last or first, 16) + 1))
        modelled = set(getattr(chip, "MODELLED", {}))
        assert modelled <= shown, f"{kind}: registers {sorted(modelled - shown)} of its MODELLED not in docs/parts.md"
        for bit in getattr(chip, "DATA_READY", ()):
            assert f"{bit.name} (0x{bit.reg:02x}, mask 0x{bit.mask:02x}) set at the output data rate" in rows["does"]
