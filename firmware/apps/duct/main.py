# Duct inspection robot (seed 002, Booysen 2008): integer P speed loops every 8 timer
# ticks, three amplitude sonars, recursive duct exploration, the record stream on a UART.
# The firmware lives in lib/; docs/duct.md has the algorithms and their seed.
import duct_robot

duct_robot.run()
