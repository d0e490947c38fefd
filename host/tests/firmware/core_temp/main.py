# The RP2040's temperature sensor, ADC channel 4, read as picozero's pico_temp_sensor and
# the rp2 docs' examples read it; ADC channel 0 and ADC(26) are one input, GP26.
from machine import ADC

sensor = ADC(ADC.CORE_TEMP)
print("R channel", ADC.CORE_TEMP)
print("R temp_u16", (sensor.read_u16(), ADC(4).read_u16()))
print("R gp26_u16", (ADC(0).read_u16(), ADC(26).read_u16()))
