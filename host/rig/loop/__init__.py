"""The run: ``RigSpec`` and ``Rig``, the conversation with the shim, the clock and its
pacing, speculation, the messages' table, how a run ends, waits, several boards in one
lockstep, a run's manifest and its replay."""
