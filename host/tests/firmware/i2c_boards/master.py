"""The master as a host program (CPython, on the set's clock): what master/main.py does,
as a Linux master's I2C code would, reading the MCU's counter and writing it commands."""


def main(board):
    i2c = board.i2c("i2c0")
    board.print("host scan", i2c.scan())
    for n in range(10):
        count = int.from_bytes(i2c.readfrom_mem(0x42, 0, 2), "little")
        board.print("host read", count, "at", board.ticks_us())
        i2c.writeto_mem(0x42, 8, bytes((n,)))
        board.sleep_ms(20)
    try:
        i2c.readfrom(0x43, 1)
    except OSError as e:
        board.print("host nobody at 0x43", e.args[0])
    board.print("host done")
