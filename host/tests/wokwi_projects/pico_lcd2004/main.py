# An LCD2004 on I2C0 (GP4 SDA, GP5 SCL; its PCF8574 at 0x3F) writing all four rows, a
# buzzer on GP15 beeping three times, and a KY-040 knob (CLK GP10, DT GP11, SW GP12)
# polled; results printed as "key value".
import time

from i2c_lcd import I2cLcd
from machine import I2C, PWM, Pin

i2c = I2C(0, sda=Pin(4), scl=Pin(5))
lcd = I2cLcd(i2c, 0x3F, 4, 20)
for row, text in enumerate(("row zero", "row one", "row two", "row three")):
    lcd.move_to(row, row)
    lcd.putstr(text)

buzzer = PWM(Pin(15))
for hz in (1000, 1500, 2000):
    buzzer.freq(hz)
    buzzer.duty_u16(20000)
    time.sleep_ms(50)
    buzzer.duty_u16(0)
    time.sleep_ms(50)
print("beeps done")

clk = Pin(10, Pin.IN, Pin.PULL_UP)
dt = Pin(11, Pin.IN, Pin.PULL_UP)
sw = Pin(12, Pin.IN, Pin.PULL_UP)
position, presses = 0, 0
last_clk, last_sw = clk.value(), sw.value()
start = time.ticks_ms()
while time.ticks_diff(time.ticks_ms(), start) < 500:
    now_clk, now_sw = clk.value(), sw.value()
    if now_clk != last_clk and now_clk == 0:
        position += 1 if dt.value() else -1
    if now_sw != last_sw and now_sw == 0:
        presses += 1
    last_clk, last_sw = now_clk, now_sw
    time.sleep_us(200)
print("position", position)
print("presses", presses)
lcd.clear()
lcd.putstr("knob %d" % position)
print("done")
while True:
    time.sleep_ms(100)
