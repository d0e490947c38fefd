# MaxBotix LV-EZ style analog sonar on an ADC: Vcc/512 volts per inch.
from machine import ADC, Pin

VREF = 3.3
M_PER_VOLT = 512 * 0.0254 / VREF


class AnalogSonar:
    def __init__(self, pin):
        self._adc = ADC(Pin(pin))
        self._adc.atten(ADC.ATTN_11DB)
        self.range_m = None

    def read_m(self):
        self.range_m = self._adc.read_u16() * VREF / 65535 * M_PER_VOLT
        return self.range_m
