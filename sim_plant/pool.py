"""The WEDA B400 pool cleaner's figures (seeds 000/001), for its rig files
(``firmware/apps/pool_cleaner/rig*.toml``: a ``tracked`` body with ``track``,
``bumper`` and ``echo_sounder`` parts, docs/parts.md) and the tests that check them.

A tracked machine, 0.90 x 0.48 m (L x W, seed 001), track separation W = 0.4 m, both
tracks at +-0.3 m/s, steered by stopping one track (:mod:`sim_plant.physics.tracked`), reversed
by its own bumper logic at the end walls. Two side-looking echo sounders measure the
distance to the long walls (:mod:`sim_plant.physics.echo_sounder`); bumpers at both ends.

Signals (the rig file's part names):

======================  ======  ==============================================================
name                    kind    meaning
======================  ======  ==============================================================
``track_l.stop``        level   1 stops the left track (seed 000: LPT 0x378 bit 1)
``track_r.stop``        level   1 stops the right track (bit 0)
``sonar.select``        level   0: left sonar (sonar 0) on the UART, 1: right (bit 2)
``sonar.uart``          bytes   NMEA ``$SDDPT`` sentences, 4800 baud, one per 500 ms
``bumper_front.out``    level   0 while the front bumper is pressed (seed 000 "bumper1")
``bumper_rear.out``     level   0 while the rear bumper is pressed ("bumper2")
======================  ======  ==============================================================

``rig-adc.toml`` has two analog sounders instead (``sonar_l.adc``, ``sonar_r.adc``, u16, a
new sample every 500 ms, ``ADC_V_PER_M`` volts per metre on a 12-bit 3.3 V ADC, 0 V for
no reading) and no select line: the harness's "ADC sonar", with the same transducer
model as the NMEA one.

The robot's reference point is the middle of the track axis; x runs along the pool
(25 m), y across it (8 m). Facing +x, the left sonar looks at the wall y = 8 m. The body is
three circles of radius W_body/2 in a row (a capsule 0.90 m long).
"""

BODY_LENGTH_M = 0.90
"""Seed 001: "30 x 48 x 90 [cm] (H x W x L)"."""
BODY_WIDTH_M = 0.48
ADC_V_PER_M = 0.33
"""ADC-sonar option: 10 m full scale at 3.3 V (a harness choice; the seed's sonar is serial)."""
BUMPER_HALF_ARC_DEG = 60.0
"""The end bumpers close for walls met within 60 deg of square on (a side wall scraped at a
shallow angle does not reverse the machine)."""
