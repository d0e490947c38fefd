ORIGIN = "firmware"  # esp is a built-in on an ESP32: a file never shadows it
