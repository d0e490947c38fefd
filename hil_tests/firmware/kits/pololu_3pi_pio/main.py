# The 3pi+ 2040's line and bump sensors read three times standing, with the PIO program of
# ir_sensors.py (Pololu's library's way): each read printed as the library returns it.
from ir_sensors import BumpSensors, LineSensors

line_sensors = LineSensors()
bump_sensors = BumpSensors()
for _ in range(3):
    print("line", list(line_sensors.read()))
    print("bump", list(bump_sensors.read()))
