ORIGIN = "firmware"  # the firmware's own, beside main.py: wins over the frozen module
