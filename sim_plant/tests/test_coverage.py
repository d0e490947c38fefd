"""The coverage grid's two ways of sweeping: a few segments cell by cell (ground truth,
every 50 ms) and many at once in arrays (the path's samples in batches). They must mark
the same cells, whatever the segments."""

import numpy as np

from sim_plant.physics.coverage import FEW_SEGMENTS, CoverageGrid
from sim_plant.world import pool


def test_a_few_segments_cell_by_cell_mark_the_cells_the_arrays_mark():
    world = pool()
    rng = np.random.default_rng(5)
    one_by_one, at_once = CoverageGrid(world, 0.1, 0.24), CoverageGrid(world, 0.1, 0.24)
    x0, y0, x1, y1 = world.bounds
    a = np.column_stack([rng.uniform(x0 - 0.5, x1 + 0.5, 400), rng.uniform(y0 - 0.5, y1 + 0.5, 400)])
    # short steps as a robot makes between samples, some long ones, some of length zero
    b = a + rng.choice([0.0, 0.015, 0.05, 0.4], size=(400, 1)) * rng.standard_normal((400, 2))
    for (ax, ay), (bx, by) in zip(a.tolist(), b.tolist()):
        one_by_one.sweep(ax, ay, bx, by)  # one segment: cell by cell
    assert len(a) > FEW_SEGMENTS
    at_once._sweep(a, b)  # many: the arrays
    assert np.array_equal(one_by_one.covered, at_once.covered), "the two ways marked different cells"
    assert one_by_one.covered_free == at_once.covered_free == int((at_once.covered & at_once.free).sum())
    assert 0.05 < at_once.fraction() < 0.9, at_once.fraction()
