import machine
from machine import ADC, PWM, Pin, Signal
from time import sleep_ms

out = Pin(26, Pin.OUT, value=0)
out.on()
sleep_ms(1)
out(0)
sleep_ms(1)
out.value(1)
led = Signal(Pin(23, Pin.IN, Pin.PULL_UP), invert=True)  # the button: pressed when low
print("R button_pressed", [led.value()])
sleep_ms(10)
print("R button_pressed_later", [led.value(), led()])
pwm = PWM(Pin(25), freq=20_000, duty_u16=1000)
sleep_ms(1)
pwm.duty_u16(30000)
print("R pwm", [pwm.freq(), pwm.duty_u16()])
sleep_ms(1)
pwm.deinit()
adc_by_pin = ADC(Pin(32))
adc_by_id = ADC(32)
print("R adc", [adc_by_pin.read_u16(), adc_by_id.read_u16()])
print("R uid", len(machine.unique_id()))
hits = []
b = Pin(34, Pin.IN)
b.irq(lambda p: hits.append(p.value()), Pin.IRQ_RISING)
state = machine.disable_irq()
sleep_ms(20)  # the edge at 15 ms waits until IRQs are enabled again
print("R while_disabled", len(hits))
machine.enable_irq(state)
for _ in range(2):  # the callback runs at a branch (scheduled: py/vm.c, pending_exception_check)
    pass
print("R after_enable", len(hits))
machine.idle()
print("R done", 1)
