"""The kernels MCU time is calibrated with (docs/mcu-time.md): ``python -m host.mcubench [INTERPRETER]``
runs them on the counting interpreter and prints the published board time beside the charged one."""
