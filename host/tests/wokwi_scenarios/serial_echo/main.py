# A Pico that asks on its console and answers, as Wokwi's serial-monitor examples do:
# input() waits for a line typed on the serial monitor (a scenario's write-serial).
from machine import Pin

led = Pin(25, Pin.OUT)
print("ready")
while True:
    command = input("> ")
    if command == "on":
        led.value(1)
    elif command == "off":
        led.value(0)
    print("ok", command)
