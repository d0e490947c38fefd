# The bench's wiring, as upstream's tests/target_wiring/esp32.py names it (MicroPython
# 1.26+ hardware tests import this module): GPIO4 to GPIO5, GPIO12 to GPIO13, and each
# UART's TX to its RX (host/conformance/inloop.py wires them).
uart_loopback_args = (1,)
uart_loopback_kwargs = {"tx": 4, "rx": 5}
pwm_loopback_pins = [(4, 5)]
encoder_loopback_id = 0
encoder_loopback_out_pins = (4, 12)
encoder_loopback_in_pins = (5, 13)
# MicroPython 1.28's machine_spi_rate.py takes its SPIs from here (their default pins), as
# upstream's esp32.py names them for an ESP32 (an ESP32-C's has SPI 1 alone).
spi_standalone_args_list = [(1,), (2,)]
