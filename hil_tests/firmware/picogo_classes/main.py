# The robot's parts as subclasses of the machine classes, each constructor passing its
# pin or id to super().__init__() (an object-oriented Pico-Go library's style, written
# here, not copied): a Pin for the IR receiver, an ADC for the battery's divider, a UART
# for the Bluetooth module (wired back to itself here).
import time
from machine import ADC, UART, Pin


class Receiver(Pin):
    def __init__(self, pin_id=5):
        super().__init__(pin_id, Pin.IN)

    @property
    def carrier(self):
        return self.value() == 0


class Battery(ADC):
    def __init__(self, pin=Pin(26)):  # noqa: B008 (the style: a default pin made at import)
        super().__init__(pin)

    @property
    def voltage(self):
        return self.read_u16() * 3.3 / 65535 * 2


class Radio(UART):
    BAUD = 115200

    def __init__(self):
        super().__init__(0, self.BAUD)

    def ask(self, text):
        self.write(text)
        self.flush()
        time.sleep_ms(5)
        return self.read() if self.any() else b""


class Led(Pin):  # (no constructor of its own: Led(25, Pin.OUT) goes to Pin's)
    pass


ir = Receiver()
battery = Battery()
radio = Radio()
led = Led(25, Pin.OUT)
led.on()
print("types", type(ir).__name__, type(battery).__name__, type(radio).__name__, type(led).__name__)
print("same pin", Pin(5).value() == ir.value(), "led", led.value())
print("battery", battery.voltage)
print("radio", radio.ask(b'{"drive": "forward"}'))
while time.ticks_ms() < 303:  # (inside the remote's 9 ms start burst, pressed at 0.3 s)
    time.sleep_ms(1)
print("carrier", int(ir.carrier), time.ticks_ms())
while time.ticks_ms() < 400:  # (its frame is over)
    time.sleep_ms(1)
print("carrier", int(ir.carrier), time.ticks_ms())
print("done")
