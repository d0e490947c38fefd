"""Worlds: wall queries, duct networks, local views, the coverage grid."""

import math

import numpy as np
import pytest

from sim_plant.physics.coverage import CoverageGrid
from sim_plant.world import (
    CANYON_END_M,
    box,
    canyon,
    duct_network,
    multi_branch_duct,
    one_right_branch_duct,
    pool,
    rectangle,
    room,
    vacuum_room,
)


def test_ray_gives_range_and_incidence():
    world = rectangle(5.0, 4.0)
    assert world.ray(1.0, 2.0, 0.0) == (4.0, 0.0)
    rng, inc = world.ray(1.0, 2.0, math.radians(20))
    assert rng == pytest.approx(4.0 / math.cos(math.radians(20)))
    assert inc == pytest.approx(math.radians(20))
    assert world.ray(1.0, 2.0, math.radians(30))[0] == pytest.approx(2.0 / math.sin(math.radians(30)))
    assert world.ray(1.0, 2.0, 0.0, max_range_m=3.0)[0] == math.inf


def test_cone_nearest_sees_the_nearest_point_inside_the_wedge():
    world = rectangle(20.0, 10.0)
    # looking along +x from (5, 1): the wall y = 0 is 1 m away but 90 deg off the axis
    assert world.cone_nearest(5.0, 1.0, 0.0, math.radians(7.5)) == pytest.approx(1.0 / math.sin(math.radians(7.5)))
    # square on to the wall x = 20: the perpendicular foot
    assert world.cone_nearest(15.0, 5.0, 0.0, math.radians(7.5)) == pytest.approx(5.0)
    # tilted 20 deg: the cone's edge at 12.5 deg is the nearest point
    assert world.cone_nearest(15.0, 5.0, math.radians(20), math.radians(7.5)) == pytest.approx(
        5.0 / math.cos(math.radians(12.5))
    )


def test_specular_returns_only_walls_whose_normal_is_in_the_cone():
    world = rectangle(10.0, 10.0)
    seen = world.specular(5.0, 5.0, math.radians(10), math.radians(35), 20.0)
    assert seen == [(pytest.approx(5.0), pytest.approx(math.radians(10)))]
    assert world.specular(5.0, 5.0, math.radians(45), math.radians(35), 20.0) == []


def test_clearance_and_normal():
    world = room(5.0, 4.0, [box(2.5, 2.0, 1.0, 1.0)])
    d, nx, ny = world.clearance(1.5, 2.0)
    assert d == pytest.approx(0.5) and (nx, ny) == pytest.approx((-1.0, 0.0))
    d, nx, ny = world.clearance(3.5, 3.0)
    assert d == pytest.approx(math.hypot(0.5, 0.5)) and (nx, ny) == pytest.approx((math.sqrt(0.5), math.sqrt(0.5)))


def test_duct_network_is_the_boundary_of_the_union_with_open_mouths():
    world = one_right_branch_duct(0.4)
    assert len(world.walls) == 8  # main duct: 2 + 1 + 2 ends; branch: 2 sides + end
    assert world.contains(0.5, 0.2) and world.contains(1.7, -0.6) and not world.contains(1.0, -0.2)
    multi = multi_branch_duct(0.4)
    for x, y in ((0.2, 0.2), (1.2, -1.0), (2.7, 2.0), (3.5, 1.7), (4.0, -0.8)):
        assert multi.contains(x, y), (x, y)
    for x, y in ((2.0, 1.0), (1.2, 1.0), (4.5, -0.5), (5.1, 0.2)):
        assert not multi.contains(x, y), (x, y)
    # from the main duct, the left branch is open upwards to its end
    assert multi.ray(2.7, 0.2, math.pi / 2)[0] == pytest.approx(2.4 + 0.2)


def test_duct_sections_that_overlap_merge():
    world = duct_network([(0, 0, 2, 1), (1, 0, 3, 1)])
    assert sorted(world.segments()) == sorted(
        [
            (0.0, 0.0, 2.0, 0.0),
            (2.0, 0.0, 3.0, 0.0),
            (0.0, 1.0, 2.0, 1.0),
            (2.0, 1.0, 3.0, 1.0),
            (0.0, 0.0, 0.0, 1.0),
            (3.0, 0.0, 3.0, 1.0),
        ]
    )


def test_local_views_answer_like_the_whole_world():
    world = multi_branch_duct()
    rng = np.random.default_rng(3)
    for _ in range(200):
        x, y = rng.uniform(0.0, 4.5), rng.uniform(-1.0, 2.5)
        a = rng.uniform(-math.pi, math.pi)
        near = world.near(x, y, 1.5)
        assert len(near.walls) < len(world.walls)
        assert near.ray(x, y, a, 1.5) == world.ray(x, y, a, 1.5)
        assert near.specular(x, y, a, 0.6, 1.5) == world.specular(x, y, a, 0.6, 1.5)
        assert near.cone_nearest(x, y, a, 0.13, 1.5) == world.cone_nearest(x, y, a, 0.13, 1.5)
        d_near, d_all = near.clearance(x, y)[0], world.clearance(x, y)[0]
        assert d_near == d_all or (d_all > 1.5 and d_near >= d_all)


def test_worlds_of_the_seeds():
    assert pool().bounds == (0.0, 0.0, 25.0, 8.0)
    assert len(vacuum_room().walls) == 4 + 4 + 4 + 3
    assert canyon().bounds[2] == pytest.approx(CANYON_END_M)
    with pytest.raises(ValueError, match="at least 3"):
        room(2, 2, [[(0, 0), (1, 1)]])


def test_coverage_grid_marks_a_capsule_around_the_path_and_only_counts_free_floor():
    world = room(4.0, 2.0, [box(3.0, 1.0, 1.0, 1.0)])
    grid = CoverageGrid(world, 0.05, 0.25)
    assert grid.free.sum() == pytest.approx((8.0 - 1.0) / 0.05**2, rel=0.01)
    for x in np.linspace(0.5, 1.5, 11):
        grid.add_point(float(x), 1.0)
    assert grid.fraction() * 7.0 == pytest.approx(1.0 * 0.5 + math.pi * 0.25**2, rel=0.05)
