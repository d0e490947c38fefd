# The 3pi+ 2040's battery level, read as the kit's library reads it (battery.py's Battery,
# written here in its style, not copied): ADC(Pin(26)), ten read_u16 averaged, through the
# board's divider of 1/11. GP26 is also the down emitters' control: driven high while the
# line sensors are read, an input after; the battery reads the same on either side of it.
from machine import ADC, Pin


class Battery:
    def __init__(self):
        self.adc = ADC(Pin(26))

    def get_level_millivolts(self):
        sum = 0
        for _ in range(10):
            sum += self.adc.read_u16()
        avg = sum / 10
        return int(3300 * avg * 11 / 65536)


battery = Battery()
print("vbat", battery.get_level_millivolts())
ir_down = Pin(26, Pin.OUT, value=1)  # (the emitters on, as the line sensors' read does)
print("emitters", ir_down.value())
ir_down.init(Pin.IN)  # (and off again)
print("vbat", Battery().get_level_millivolts())
print("done")
