"""Behaviour diff of two trace folders (``mpy-fil diff A B``, ``docs/testing-tools.md``):
two firmware versions, or a run and its replay.

- :mod:`.compare`: trajectories, outputs and budgets compared, and the verdict against
  thresholds;
- :mod:`.plot`: both runs drawn on one figure (PNG);
- :mod:`.command`: the command: a table, the plot's path, the exit status.
"""
