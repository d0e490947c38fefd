# _hilfast: the shim's hot path in C (host/shim/cmod/_hilfast/_hilfast.c), linked into the
# harness's MicroPython build as a user C module (host/core/interpreter.py, USER_C_MODULES).
HILFAST_MOD_DIR := $(USERMOD_DIR)
SRC_USERMOD_C += $(HILFAST_MOD_DIR)/_hilfast.c
