"""Shrinking a failing run to a minimal one that fails the same way
(``docs/testing-tools.md``): delta debugging over its fault list, then each fault's window,
then the duration.

- :mod:`.signature`: what "fails the same way" means (a run's failure signature);
- :mod:`.ddmin`: delta debugging over a list, a round's candidates tried together;
- :mod:`.runs`: the runs themselves, in this process or on the campaign's process pool;
- :mod:`.source`: the run to shrink, from a trace folder or a campaign's run;
- :mod:`.shrinker`: the three phases and what they removed;
- :mod:`.command`: ``mpy-fil shrink`` and ``mpy-fil campaign --shrink``.
"""
