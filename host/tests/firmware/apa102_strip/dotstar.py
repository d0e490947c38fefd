# An APA102 ("DotStar") strip driver written as the public MicroPython ones are: a buffer of
# (r, g, b) pixels and a global brightness, sent over SPI as a start frame of four zero
# bytes, a 0xE0 | brightness, blue, green, red frame per LED, and an end frame of ones
# (a byte per 16 LEDs, at least four).


class DotStar:
    def __init__(self, spi, n, brightness=31):
        self.spi = spi
        self.n = n
        self.brightness = brightness
        self.pixels = [(0, 0, 0)] * n

    def __setitem__(self, i, rgb):
        self.pixels[i] = rgb

    def __getitem__(self, i):
        return self.pixels[i]

    def __len__(self):
        return self.n

    def fill(self, rgb):
        for i in range(self.n):
            self.pixels[i] = rgb

    def show(self):
        buf = bytearray(4 + 4 * self.n + max(4, (self.n + 15) // 16))
        head = 0xE0 | (self.brightness & 0x1F)
        for i, (r, g, b) in enumerate(self.pixels):
            at = 4 + 4 * i
            buf[at] = head
            buf[at + 1] = b
            buf[at + 2] = g
            buf[at + 3] = r
        for at in range(4 + 4 * self.n, len(buf)):
            buf[at] = 0xFF
        self.spi.write(buf)
