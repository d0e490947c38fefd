# An LCD1602 on I2C (its PCF8574 at 0x27), a buzzer on D15 playing two tones, a KY-040
# knob (CLK D32, DT D33, SW D25) counted in a CLK IRQ; results printed as "key value".
import time

from i2c_lcd import I2cLcd
from machine import I2C, PWM, Pin

i2c = I2C(0, scl=Pin(22), sda=Pin(21), freq=400000)
lcd = I2cLcd(i2c, 0x27, 2, 16)
lcd.putstr("Hello Wokwi\nLCD 1602")
print("found", [hex(a) for a in i2c.scan()])

buzzer = PWM(Pin(15), freq=440, duty_u16=32768)
time.sleep_ms(100)
buzzer.freq(880)
time.sleep_ms(100)
buzzer.duty_u16(0)
print("tones done")

clk = Pin(32, Pin.IN)
dt = Pin(33, Pin.IN)
sw = Pin(25, Pin.IN, Pin.PULL_UP)
position = 0
pressed_at = []


def turned(pin):
    global position
    position += 1 if dt.value() else -1


def pressed(pin):
    pressed_at.append(position)


clk.irq(trigger=Pin.IRQ_FALLING, handler=turned)
sw.irq(trigger=Pin.IRQ_FALLING, handler=pressed)
start = time.ticks_ms()
while time.ticks_diff(time.ticks_ms(), start) < 600:
    time.sleep_ms(10)
print("position", position)
print("pressed", pressed_at)
lcd.move_to(0, 1)
lcd.putstr("pos %d      " % position)
print("done")
while True:
    time.sleep_ms(100)
