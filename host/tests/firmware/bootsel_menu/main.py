# A menu that waits for the BOOTSEL button, as kit demos do: press to start, each press
# after that picks the next item; the rig file presses it (host/tests/test_pin_family.py).
import rp2
import time

t0 = time.ticks_ms()
print("R idle", rp2.bootsel_button())
while not rp2.bootsel_button():
    time.sleep_ms(10)
print("R started_ms", time.ticks_diff(time.ticks_ms(), t0))
item = 0
while item < 2:
    while rp2.bootsel_button():  # (let go first)
        time.sleep_ms(10)
    while not rp2.bootsel_button():
        time.sleep_ms(10)
    item += 1
    print("R item%d_ms" % item, time.ticks_diff(time.ticks_ms(), t0))
