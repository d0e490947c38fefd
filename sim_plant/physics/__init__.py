"""The physics of catalogue parts: each module is named after the part (or body) of
:mod:`sim_plant.catalogue` whose behaviour it models (``physics/hcsr04.py`` is the
``hcsr04`` part's echo timing; ``physics/tracked.py`` the ``tracked`` body's track drive),
while the catalogue module of that name declares the part (options with bounds, signals,
truth, views). Only the catalogue imports this package (and tests, which measure the
physics alone); ``host/tests/test_architecture.py`` holds that rule. Models that several
parts share (the drive train, sonars' geometry, buses, the world) live one level up.
"""
