"""Firmware in the loop: the :class:`Rig` and its parts (targets, pacing, speculation,
wiring, budgets), the apps it knows, and replays."""
