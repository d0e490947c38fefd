# ESP32 RC car: an SG90 servo steers the front wheels, an L298N drives the rear motor, an
# HC-SR04 looks ahead, and the 2S battery is read on GPIO 34 through a 100k/47k divider;
# the on-board LED (GPIO 2) lights when the battery runs low. It drives ahead and steers
# left around whatever is within 50 cm, then straightens up; below 6.6 V it stops.
# Plain MicroPython as on the board: test_esp32_car.py runs it against a simulated car.
import time

from machine import ADC, PWM, Pin, time_pulse_us

# --- pins --------------------------------------------------------------------------
SERVO_PIN = 13
ENA, IN1, IN2 = 25, 26, 27
TRIG, ECHO = 5, 18
BATT_PIN = 34
LED_PIN = 2

# --- tuning ------------------------------------------------------------------------
CENTER = 90  # servo degrees with the wheels straight
LEFT = 130  # servo degrees: full left
AVOID_CM = 50
CRUISE = 0.6  # motor duty, 0..1
DIVIDER = (100 + 47) / 47  # battery volts per ADC volt
LOW_V = 7.0
CUTOFF_V = 6.6
LOOP_MS = 60

servo = PWM(Pin(SERVO_PIN), freq=50)
ena = PWM(Pin(ENA), freq=1000)
in1 = Pin(IN1, Pin.OUT)
in2 = Pin(IN2, Pin.OUT)
trig = Pin(TRIG, Pin.OUT)
echo = Pin(ECHO, Pin.IN)
adc = ADC(Pin(BATT_PIN))
adc.atten(ADC.ATTN_11DB)  # full range 0..3.3 V
led = Pin(LED_PIN, Pin.OUT)


def steer(angle):
    """Servo angle 0..180 degrees: a 0.5..2.5 ms pulse every 20 ms."""
    angle = max(0, min(180, angle))
    servo.duty_ns(int((500 + angle * 2000 / 180) * 1000))


def drive(speed):
    """Rear motor, -1..1."""
    in1.value(1 if speed > 0 else 0)
    in2.value(1 if speed < 0 else 0)
    ena.duty_u16(int(min(abs(speed), 1) * 65535))


def distance_cm():
    trig.value(0)
    time.sleep_us(2)
    trig.value(1)
    time.sleep_us(10)
    trig.value(0)
    t = time_pulse_us(echo, 1, 30000)
    if t < 0:
        return 999  # nothing in range
    return t / 58


def battery_v():
    raw = 0
    for _ in range(8):
        raw += adc.read()
    return raw / 8 / 4095 * 3.3 * DIVIDER


steer(CENTER)
drive(0)
print("esp32 car ready")
time.sleep_ms(500)

last_report = time.ticks_ms()
avoiding = False
while True:
    v = battery_v()
    if time.ticks_diff(time.ticks_ms(), last_report) >= 1000:
        last_report = time.ticks_ms()
        print("battery %.2f V" % v)
    if v < LOW_V and not led.value():
        led.value(1)
        print("low battery %.2f V" % v)
    if v < CUTOFF_V:
        drive(0)
        steer(CENTER)
        print("battery flat, stopped")
        break
    d = distance_cm()
    if d < AVOID_CM:
        if not avoiding:
            print("obstacle at %d cm: steering left" % d)
            avoiding = True
        steer(LEFT)
        drive(CRUISE * 0.7)
    else:
        avoiding = False
        steer(CENTER)
        drive(CRUISE)
    time.sleep_ms(LOOP_MS)
