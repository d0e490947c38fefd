# An ST7789 driver in the shape of russhughes' st7789py (lib/st7789py.py), written here, not
# copied: a rotation table per panel (MADCTL, width, height, column and row offsets), a
# window (CASET, RASET, RAMWR) per drawing, fill_rect in chunks of 256 pixels, colours
# sent big-endian, text from a font module (WIDTH, HEIGHT, FIRST, LAST, FONT) blitted a
# glyph at a time, and its init: each command with a zero byte after it.
import struct
import time

RGB, BGR = 0x00, 0x08
BLACK, RED, GREEN, BLUE, YELLOW, WHITE = 0x0000, 0xF800, 0x07E0, 0x001F, 0xFFE0, 0xFFFF
ROTATIONS_135x240 = (  # (MADCTL, width, height, column offset, row offset)
    (0x00, 135, 240, 52, 40),
    (0x60, 240, 135, 40, 53),
    (0xC0, 135, 240, 53, 40),
    (0xA0, 240, 135, 40, 52),
)
INIT = (  # (command, its data, then a wait in ms): SLPOUT, NORON, COLMOD 16 bits, INVON, DISPON
    (b"\x11", b"\x00", 120),
    (b"\x13", b"\x00", 0),
    (b"\x3a", b"\x55", 10),
    (b"\x21", b"\x00", 0),
    (b"\x29", b"\x00", 120),
)
CHUNK = 256  # pixels a write


class ST7789:
    def __init__(self, spi, width, height, reset, dc, cs, backlight, rotation=0, color_order=BGR):
        self.spi, self.reset, self.dc, self.cs, self.backlight = spi, reset, dc, cs, backlight
        self.rotations = ROTATIONS_135x240  # (this one knows the 135 x 240 panel only)
        self.color_order = color_order
        self.hard_reset()
        for command, data, delay_ms in INIT:
            self._write(command, data)
            time.sleep_ms(delay_ms)
        self.rotation(rotation)
        self.fill(BLACK)
        backlight.value(1)

    def _write(self, command=None, data=None):
        self.cs.off()
        if command is not None:
            self.dc.off()
            self.spi.write(command)
        if data is not None:
            self.dc.on()
            self.spi.write(data)
            self.cs.on()

    def hard_reset(self):
        self.cs.off()
        self.reset.on()
        time.sleep_ms(10)
        self.reset.off()
        time.sleep_ms(10)
        self.reset.on()
        time.sleep_ms(120)
        self.cs.on()

    def rotation(self, rotation):
        madctl, self.width, self.height, self.xstart, self.ystart = self.rotations[rotation % 4]
        self._write(b"\x36", bytes([madctl | self.color_order]))

    def _window(self, x0, y0, x1, y1):
        self._write(b"\x2a", struct.pack(">HH", x0 + self.xstart, x1 + self.xstart))
        self._write(b"\x2b", struct.pack(">HH", y0 + self.ystart, y1 + self.ystart))
        self._write(b"\x2c")

    def fill_rect(self, x, y, w, h, color):
        self._window(x, y, x + w - 1, y + h - 1)
        chunks, rest = divmod(w * h, CHUNK)
        one = struct.pack(">H", color)
        for _ in range(chunks):
            self._write(None, one * CHUNK)
        if rest:
            self._write(None, one * rest)

    def fill(self, color):
        self.fill_rect(0, 0, self.width, self.height, color)

    def pixel(self, x, y, color):
        self._window(x, y, x, y)
        self._write(None, struct.pack(">H", color))

    def rect(self, x, y, w, h, color):
        self.fill_rect(x, y, w, 1, color)
        self.fill_rect(x, y, 1, h, color)
        self.fill_rect(x + w - 1, y, 1, h, color)
        self.fill_rect(x, y + h - 1, w, 1, color)

    def blit_buffer(self, buffer, x, y, w, h):
        self._window(x, y, x + w - 1, y + h - 1)
        self._write(None, buffer)

    def text(self, font, string, x, y, color=WHITE, background=BLACK):
        fg, bg = struct.pack(">H", color), struct.pack(">H", background)
        for ch in string:
            c = ord(ch)
            if font.FIRST <= c < font.LAST and x + font.WIDTH <= self.width:
                glyph = font.FONT[(c - font.FIRST) * font.HEIGHT : (c - font.FIRST + 1) * font.HEIGHT]
                buffer = b"".join(fg if row << i & 0x80 else bg for row in glyph for i in range(8))
                self.blit_buffer(buffer, x, y, font.WIDTH, font.HEIGHT)
            x += font.WIDTH
