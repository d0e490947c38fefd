"""Wokwi's boards: which chip family each is (the rig's ``[board] family``) and what its
pin names mean: a GPIO (``esp:D13``, ``esp:13``, ``pico:GP15``), ground, a supply rail
(3.3 V or 5 V), or a pin of no use to a rig (``EN``, ``RUN``, the flash pins)."""

import re
from dataclasses import dataclass

GND, V3, V5 = "gnd", 3.3, 5.0


@dataclass(frozen=True)
class Board:
    """A Wokwi board: its ``family`` (ours), its name in our words, its GPIO pins by name
    (``gpio(name)``: the number, or None), its highest GPIO."""

    wokwi: str
    family: str
    title: str
    style: str  # how its pins are named: "devkit_v1" (D13), "number" (13), "pico" (GP15)
    highest: int
    named: tuple = ()  # (name, GPIO) pairs beyond the style's own: TX, RX, VP, VN

    def gpio(self, pin: str) -> int | None:
        """The GPIO a pin name is, or None (a rail, or a pin a rig has no use for)."""
        named = dict(self.named)
        if pin in named:
            return named[pin]
        pattern = {"devkit_v1": r"D(\d{1,9})", "number": r"(\d{1,9})", "pico": r"GP(\d{1,9})"}[self.style]
        m = re.fullmatch(pattern, pin)
        if m and int(m.group(1)) <= self.highest:
            return int(m.group(1))
        return None

    def key(self, pin: str) -> str:
        """The pin's name in the rig's ``[board.pins]``: the board's own (D13, GP15), or
        GPIO13 for a bare number."""
        return f"GPIO{pin}" if pin.isdigit() else pin


def rail(pin: str) -> object:
    """``GND``, ``3.3`` or ``5.0`` for a board's ground or supply pin (``GND.2``, ``3V3``,
    ``VIN``, ``VBUS``), else None."""
    base = pin.split(".")[0]
    if base in ("GND", "AGND", "VSS"):
        return GND
    if base in ("3V3", "3.3V", "VCC"):
        return V3
    if base in ("5V", "VIN", "VBUS", "VSYS"):
        return V5
    return None


ESP32_V1 = (("TX0", 1), ("RX0", 3), ("TX2", 17), ("RX2", 16), ("VP", 36), ("VN", 39))
ESP32_C = (("TX", 1), ("RX", 3), ("VP", 36), ("VN", 39))
BOARDS = {
    b.wokwi: b
    for b in (
        Board("wokwi-esp32-devkit-v1", "esp32", "ESP32 DevKit v1", "devkit_v1", 39, ESP32_V1),
        Board("board-esp32-devkit-c-v4", "esp32", "ESP32 DevKitC v4", "number", 39, ESP32_C),
        Board("board-esp32-s3-devkitc-1", "esp32", "ESP32-S3 DevKitC-1", "number", 48, (("TX", 43), ("RX", 44))),
        Board("board-esp32-c3-devkitm-1", "esp32", "ESP32-C3 DevKitM-1", "number", 21, (("TX", 21), ("RX", 20))),
        Board("wokwi-pi-pico", "rpi_pico", "Raspberry Pi Pico", "pico", 28),
        Board("wokwi-pi-pico-w", "rpi_pico", "Raspberry Pi Pico W", "pico", 28),
        Board("board-pi-pico-w", "rpi_pico", "Raspberry Pi Pico W", "pico", 28),
    )
}
"""Wokwi's board types we run, by type."""

BOARD_ATTRS = ("env", "builder", "serialInterface", "flashSize", "cpuFrequency")
"""A board's attributes: which MicroPython image, build, console and clock Wokwi uses.
Here the firmware runs on our interpreter at its own speed: they change nothing."""
