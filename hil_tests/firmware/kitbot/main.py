# kitbot's demo: the robot starts when BOOTSEL is pressed, drives straight ahead at half
# speed for 600 ms reading its line sensors every 20 ms, then turns in place for 300 ms,
# and shows its encoder counts on the display and its state on the RGB LEDs. Each
# measurement is printed as "R name value" for the test beside the rig file.
import time

from kitbot import IMU, ButtonA, Display, Encoders, LineSensors, Motors, RGBLEDs, bootsel_pressed

display = Display()
display.text("kitbot", 0, 0, 1)
display.text("press BOOTSEL", 0, 16, 1)
display.show()
imu = IMU()
print("R detect", imu.detect())
print("R reset_polls", imu.reset())
imu.enable_default()
leds = RGBLEDs()
motors = Motors()
encoders = Encoders()
line = LineSensors()
button = ButtonA()

t0 = time.ticks_ms()
while not bootsel_pressed():
    time.sleep_ms(10)
print("R started_ms", time.ticks_diff(time.ticks_ms(), t0))
print("R button_a", button.is_pressed())
time.sleep_ms(5)
print("R acc", list(imu.acc.read()))
print("R gyro_still", list(imu.gyro.read()))
print("R mag", list(imu.mag.read()))

encoders.get_counts(reset=True)
leds.set(0, (0, 255, 0))
leds.show()
readings = []
motors.set_speeds(3000, 3000)  # half of MAX_SPEED on both wheels
start = time.ticks_us()
print("R regs", motors.registers())
while time.ticks_diff(time.ticks_us(), start) < 600_000:
    data = line.read()
    readings.append([time.ticks_diff(time.ticks_us(), start) // 1000] + list(data))
    time.sleep_ms(20)
motors.off()
print("R drive_us", time.ticks_diff(time.ticks_us(), start))
print("R drive_counts", list(encoders.get_counts(reset=True)))
print("R line", readings)
print("R one", [line.read_one(i) for i in range(3)])

leds.set(0, (0, 0, 255))
leds.show()
motors.set_speeds(-2000, 2000)
start = time.ticks_us()
time.sleep_ms(150)
print("R gyro_turn", list(imu.gyro.read()))
time.sleep_ms(150)
motors.off()
print("R turn_us", time.ticks_diff(time.ticks_us(), start))
counts = encoders.get_counts()
print("R turn_counts", list(counts))

leds.set(0, (255, 0, 0))
leds.show()
display.fill(0)
display.text("kitbot done", 0, 0, 1)
totals = (encoders.left.read(), encoders.right.read())
print("R totals", list(totals))
display.text("L %d" % totals[0], 0, 16, 1)
display.text("R %d" % totals[1], 0, 28, 1)
display.rect(0, 44, 128, 20, 1)
display.show()
print("R picture", repr(bytes(display.buffer).hex()))
