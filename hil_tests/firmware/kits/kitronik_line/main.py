# A line follower in the style of Kitronik's Basic3SensorLineFollow.py (written here, not
# copied), on their library: the button starts it (an IRQ, as their tutorials set one), the
# centre sensor over the dark line drives ahead, otherwise the side that reads lighter says
# which way the buggy went and one motor reverses to turn it back; the ZIP LEDs say which
# (green ahead, yellow on the side it turns to), every 10 ms. It prints "lost" if all three
# sensors read the light floor for 300 ms together.
from machine import Pin
from time import sleep_ms, ticks_diff, ticks_ms

from PicoAutonomousRobotics import KitronikPicoRobotBuggy

SPEED = 50  # of 100 (their demo's 75 wiggles more on a tight course)
DARK = 30000  # their demo's threshold: a read_u16 over the line is higher

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
print("start", buggy.getRawLFValue("l"), buggy.getRawLFValue("c"), buggy.getRawLFValue("r"))
light_since = None
while True:
    leftVal = buggy.getRawLFValue("l")
    rightVal = buggy.getRawLFValue("r")
    centerVal = buggy.getRawLFValue("c")
    if centerVal < DARK:
        if leftVal < rightVal:  # the line is to the right: turn right
            buggy.setLED(0, buggy.YELLOW)
            buggy.setLED(1, buggy.RED)
            buggy.setLED(2, buggy.RED)
            buggy.setLED(3, buggy.YELLOW)
            buggy.motorOn("l", "f", SPEED)
            buggy.motorOn("r", "r", SPEED)
        elif rightVal < leftVal:  # to the left
            buggy.setLED(0, buggy.RED)
            buggy.setLED(1, buggy.YELLOW)
            buggy.setLED(2, buggy.YELLOW)
            buggy.setLED(3, buggy.RED)
            buggy.motorOn("l", "r", SPEED)
            buggy.motorOn("r", "f", SPEED)
        if max(leftVal, rightVal) < DARK:
            if light_since is None:
                light_since = ticks_ms()
            elif ticks_diff(ticks_ms(), light_since) > 300:
                print("lost")
                light_since = ticks_ms()
        else:
            light_since = None
    else:
        light_since = None
        for led in range(4):
            buggy.setLED(led, buggy.GREEN)
        buggy.motorOn("l", "f", SPEED)
        buggy.motorOn("r", "f", SPEED)
    buggy.show()
    sleep_ms(10)
