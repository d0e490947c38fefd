"""Part ``lsm6dso``: an ST LSM6DSO 6-axis IMU as robot kits wire it, SA0 high at I2C 0x6B
(0x6A with SA0 low; or SPI, chip select ``<name>.cs``), fed by the body's motion.

The LSM6DSO datasheet (DocID031470) gives the same identity as the LSM6DSOX's (WHO_AM_I
0x0F reads 0x6C) and, for every register the ``lsm6dsox`` part models, the same address,
bits and reset behaviour (9.14 CTRL3_C, 9.26 STATUS_REG): the chip is that part's
(:mod:`sim_plant.catalogue.lsm6dsox`, its registers in docs/parts.md), at this address."""

from sim_plant.catalogue.imu import ImuPart
from sim_plant.catalogue.lsm6dsox import WHO_AM_I_OPTION, Lsm6dsox


class Lsm6dso(Lsm6dsox):
    kind = "lsm6dso"
    doc = "An LSM6DSO 6-axis IMU (WHO_AM_I 0x6C, the lsm6dsox part's registers) at 0x6B, SA0 high as kits wire it."
    OPTIONS = (*ImuPart.bus_options(0x6B), WHO_AM_I_OPTION)
