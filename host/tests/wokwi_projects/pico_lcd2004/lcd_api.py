# A character LCD (HD44780) API, in the shape of the lcd_api.py most MicroPython LCD
# projects carry: the commands and the cursor bookkeeping here, the bus in a subclass
# (hal_write_command, hal_write_data). Written for these tests.
import time


class LcdApi:
    CLR = 0x01
    HOME = 0x02
    ENTRY_MODE = 0x04
    ENTRY_INC = 0x02
    ON_CTRL = 0x08
    ON_DISPLAY = 0x04
    ON_CURSOR = 0x02
    ON_BLINK = 0x01
    FUNCTION = 0x20
    FUNCTION_2LINES = 0x08
    FUNCTION_RESET = 0x30
    CGRAM = 0x40
    DDRAM = 0x80

    def __init__(self, num_lines, num_columns):
        self.num_lines = min(num_lines, 4)
        self.num_columns = min(num_columns, 40)
        self.cursor_x = 0
        self.cursor_y = 0
        self.implied_newline = False
        self.backlight = True
        self.display_off()
        self.backlight_on()
        self.clear()
        self.hal_write_command(self.ENTRY_MODE | self.ENTRY_INC)
        self.hide_cursor()
        self.display_on()

    def clear(self):
        self.hal_write_command(self.CLR)
        self.hal_write_command(self.HOME)
        self.cursor_x = 0
        self.cursor_y = 0

    def show_cursor(self):
        self.hal_write_command(self.ON_CTRL | self.ON_DISPLAY | self.ON_CURSOR)

    def hide_cursor(self):
        self.hal_write_command(self.ON_CTRL | self.ON_DISPLAY)

    def display_on(self):
        self.hal_write_command(self.ON_CTRL | self.ON_DISPLAY)

    def display_off(self):
        self.hal_write_command(self.ON_CTRL)

    def backlight_on(self):
        self.backlight = True
        self.hal_backlight_on()

    def backlight_off(self):
        self.backlight = False
        self.hal_backlight_off()

    def move_to(self, cursor_x, cursor_y):
        self.cursor_x = cursor_x
        self.cursor_y = cursor_y
        addr = cursor_x & 0x3F
        if cursor_y & 1:
            addr += 0x40  # rows 1 and 3
        if cursor_y & 2:
            addr += self.num_columns  # rows 2 and 3 go on from rows 0 and 1
        self.hal_write_command(self.DDRAM | addr)

    def putchar(self, char):
        if char == "\n":
            if not self.implied_newline:
                self.cursor_x = self.num_columns
        else:
            self.hal_write_data(ord(char))
            self.cursor_x += 1
        if self.cursor_x >= self.num_columns:
            self.cursor_x = 0
            self.cursor_y = (self.cursor_y + 1) % self.num_lines
            self.implied_newline = char != "\n"
            self.move_to(self.cursor_x, self.cursor_y)

    def putstr(self, string):
        for char in string:
            self.putchar(char)

    def custom_char(self, location, charmap):
        self.hal_write_command(self.CGRAM | ((location & 7) << 3))
        time.sleep_us(40)
        for row in charmap[:8]:
            self.hal_write_data(row)
            time.sleep_us(40)
        self.move_to(self.cursor_x, self.cursor_y)

    def hal_backlight_on(self):
        pass

    def hal_backlight_off(self):
        pass

    def hal_write_command(self, cmd):
        raise NotImplementedError

    def hal_write_data(self, data):
        raise NotImplementedError
