# The buggy's first outing, written the way Kitronik's demos use their library: the button
# starts it (an IRQ), the ZIP LEDs say what it does, and it drives until the front
# ultrasonic sees the wall 15 cm away, then stops and sounds the horn.
from machine import Pin
from time import sleep_ms

from PicoAutonomousRobotics import KitronikPicoRobotBuggy

buggy = KitronikPicoRobotBuggy()
started = False


def on_button(pin):
    global started
    started = True


buggy.button.irq(trigger=Pin.IRQ_RISING, handler=on_button)
for led in range(4):
    buggy.setLED(led, buggy.BLUE)
buggy.show()
while not started:
    sleep_ms(10)
print("floor", buggy.getRawLFValue("l"), buggy.getRawLFValue("c"), buggy.getRawLFValue("r"))
print("rear", buggy.getDistance("r"))
for led in range(4):
    buggy.setLED(led, buggy.GREEN)
buggy.show()
while True:
    front = buggy.getDistance("f")
    if 0 < front <= 15:
        break
    buggy.motorOn("l", "f", 60)
    buggy.motorOn("r", "f", 60)
    sleep_ms(20)
buggy.motorOff("l")
buggy.motorOff("r")
sleep_ms(300)
print("wall_cm", buggy.getDistance("f"))
for led in range(4):
    buggy.setLED(led, buggy.RED)
buggy.show()
buggy.beepHorn()
print("done")
