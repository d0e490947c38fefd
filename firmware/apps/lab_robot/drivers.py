# The lab robot's hardware: DRV8833 motor channels, quadrature encoders counted in
# Pin.irq handlers, and MaxBotix LV-EZ analog sonars chained on one RX line.
from machine import ADC, PWM, Pin, disable_irq, enable_irq
from time import sleep_us

from quadrature import Quadrature

PWM_FREQ_HZ = 20_000  # above hearing; the DRV8833 takes up to 250 kHz
MM_PER_U16 = 512 * 25.4 / 65535  # LV-EZ analog law, Vcc/512 per inch, read ratiometric
RX_PULSE_US = 25  # "hold RX high for 20 us or more to command a range reading"


class Drv8833Motor:
    """One DRV8833 channel: PWM on IN1 drives forwards, on IN2 backwards, both low coast."""

    def __init__(self, in1, in2):
        self._in1 = PWM(Pin(in1, Pin.OUT), freq=PWM_FREQ_HZ, duty_u16=0)
        self._in2 = PWM(Pin(in2, Pin.OUT), freq=PWM_FREQ_HZ, duty_u16=0)
        self.duty = 0.0

    def drive(self, duty):
        """duty in -1.0 .. 1.0: the sign is the direction."""
        self.duty = duty = max(-1.0, min(1.0, duty))
        d = int(abs(duty) * 65535)
        self._in1.duty_u16(d if duty > 0 else 0)
        self._in2.duty_u16(d if duty < 0 else 0)


class QuadratureEncoder:
    """Both channels on interrupts, both edges: each handler reads A and B and steps the
    Table 1 decoder (quadrature.py). On the ESP32 a pin's handler is always scheduled (its
    Pin.irq has no hard argument): it runs at the next bytecode boundary, not inside a
    blocking call such as the sonar's time_pulse_us."""

    def __init__(self, pin_a, pin_b):
        self._a = Pin(pin_a, Pin.IN)
        self._b = Pin(pin_b, Pin.IN)
        self.decoder = Quadrature(self._a.value(), self._b.value())
        self._taken = 0
        edges = Pin.IRQ_RISING | Pin.IRQ_FALLING
        self._a.irq(handler=self._edge, trigger=edges)
        self._b.irq(handler=self._edge, trigger=edges)

    def _edge(self, _pin):
        self.decoder.edge(self._a.value(), self._b.value())

    def take(self):
        """Net counts since the last call (read with interrupts off: a handler may step
        the count between two reads)."""
        state = disable_irq()
        count = self.decoder.count
        enable_irq(state)
        n = count - self._taken
        self._taken = count
        return n


class SonarChain:
    """Analog sonars whose RX lines share one GPIO: ``trigger()`` starts a ranging of
    all of them, ``read_mm()`` gives each one's range once it is done (49 ms later)."""

    def __init__(self, rx, adc_pins):
        self._rx = Pin(rx, Pin.OUT, value=0)
        self._adcs = [ADC(Pin(p)) for p in adc_pins]
        if hasattr(ADC, "ATTN_11DB"):  # ESP32: the full 0..3.3 V span
            for adc in self._adcs:
                adc.atten(ADC.ATTN_11DB)

    def trigger(self):
        self._rx.value(1)
        sleep_us(RX_PULSE_US)
        self._rx.value(0)

    def read_mm(self):
        return [adc.read_u16() * MM_PER_U16 for adc in self._adcs]
