# A font module in st7789py's shape (8 x 8, a byte a row, the top bit leftmost): two
# glyphs of our own, "H" (0x48) and "I" (0x49).
WIDTH = 8
HEIGHT = 8
FIRST = 0x48
LAST = 0x4A
FONT = b"\x81\x81\x81\xff\x81\x81\x81\x00" + b"\x3c\x18\x18\x18\x18\x18\x3c\x00"
