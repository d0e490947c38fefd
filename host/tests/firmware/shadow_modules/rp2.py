ORIGIN = "firmware"  # an ESP32 has no rp2: the firmware's file is found
