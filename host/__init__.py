"""Host side of the firmware-in-the-loop harness (CPython).

The rig (:class:`host.rig.Rig`) starts MicroPython's unix port with the shim in
``host/shim`` ahead of the built-in ``machine`` and ``time``, talks to it over a pty
(:mod:`host.link`), advances the plant in virtual time, and keeps timing budgets and
traces.
"""
