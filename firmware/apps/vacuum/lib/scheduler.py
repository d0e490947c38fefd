# A cooperative scheduler on a fixed quantum, as seed 003 §4.1 allots its tasks: each task
# runs every so many quanta (pose 100 ms = 2, sensing 150 ms = 3, the behaviour switch
# 500 ms = 10 of 50 ms), in a fixed order within its quantum. Pure Python.


class QuantumScheduler:
    def __init__(self, tasks):
        """tasks: (name, every_n_quanta) in the order they run within a quantum."""
        cycle = 1
        for _, every in tasks:
            cycle = cycle * every // _gcd(cycle, every)
        # the pattern repeats after `cycle` quanta: planned once, nothing allocated per quantum
        self._plan = tuple(tuple(name for name, every in tasks if q % every == 0) for q in range(cycle))
        self.quantum = 0

    def due(self):
        """The names of the tasks due in the current quantum, then on to the next one."""
        q = self.quantum
        self.quantum = (q + 1) % len(self._plan)
        return self._plan[q]


def _gcd(a, b):
    while b:
        a, b = b, a % b
    return a
