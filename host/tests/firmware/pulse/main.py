from machine import Pin, time_pulse_us

echo = Pin(36, Pin.IN)
print("R pulse", time_pulse_us(echo, 1, 30_000))  # starts at 10 ms, lasts 583 us
print("R no_start", time_pulse_us(echo, 1, 5_000))  # nothing for 5 ms: -2
print("R too_long", time_pulse_us(echo, 1, 30_000))  # rises at 40 ms, lasts 60 ms: -1
