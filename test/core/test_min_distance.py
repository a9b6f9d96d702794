"""Minimum distance (closest points, GJK/EPA on exact primitives) against analytic cases:
sphere-box (face, edge, corner, rotated, penetrating), capsule-capsule (against the closed-form
closest points of two segments), a vertical cylinder (the operator's body) against a box in the
world, and the grouped query a safety supervisor makes per link."""
import math

import numpy as np
import pytest
from conftest import GREY, IDENTITY, yaw_quaternion

from epuck_vrep_compat import _core

Shape = _core.ConvexShape
TOL_M = 1e-6        # GJK stops at a relative improvement of ~1e-6: micrometres at metres


def sphere_box_distance(centre, radius, half, position, yaw):
    """Signed distance of a sphere to a box turned by yaw about z (closed form)."""
    c, s = math.cos(-yaw), math.sin(-yaw)
    d = np.asarray(centre, float) - position
    local = np.array([c * d[0] - s * d[1], s * d[0] + c * d[1], d[2]])
    outside = np.abs(local) - half
    if (outside > 0).any():
        return float(np.linalg.norm(np.maximum(outside, 0.0))) - radius
    return float(outside.max()) - radius           # inside: minus (depth to the nearest face)


@pytest.mark.parametrize("centre", [(0.9, 0.1, 0.2),      # face
                                    (0.8, 0.6, 0.0),      # edge
                                    (0.7, -0.5, 0.6),     # corner
                                    (-0.6, 0.1, -0.5),    # edge below
                                    (0.15, 0.05, 0.0)])   # centre inside: penetration
@pytest.mark.parametrize("yaw", [0.0, 0.6])
def test_sphere_box_matches_the_closed_form(centre, yaw):
    half, position, radius = np.array([0.3, 0.2, 0.25]), np.array([0.1, 0.0, 0.05]), 0.12
    distance, on_sphere, on_box = _core.closest_points(
        Shape.sphere(radius), centre, IDENTITY, Shape.box(half), position, IDENTITY
        if yaw == 0.0 else yaw_quaternion(yaw))
    expected = sphere_box_distance(centre, radius, half, position, yaw)
    assert distance == pytest.approx(expected, abs=TOL_M)
    # the witnesses: the box point on its surface, the sphere point on its surface, the
    # segment between them as long as the distance
    assert np.linalg.norm(on_sphere - np.asarray(centre)) == pytest.approx(radius, abs=TOL_M)
    assert np.linalg.norm(on_sphere - on_box) == pytest.approx(abs(expected), abs=TOL_M)


def segment_closest(p1, q1, p2, q2):
    """Closest points of segments p1q1 and p2q2 (Ericson, Real-Time Collision Detection 5.1.9),
    for segments of non-zero length."""
    d1, d2, r = q1 - p1, q2 - p2, p1 - p2
    a, e, f = d1 @ d1, d2 @ d2, d2 @ r
    c, b = d1 @ r, d1 @ d2
    denom = a * e - b * b
    s = float(np.clip((b * f - c * e) / denom, 0, 1)) if denom > 1e-15 else 0.0
    t = (b * s + f) / e
    if t < 0:
        t, s = 0.0, float(np.clip(-c / a, 0, 1))
    elif t > 1:
        t, s = 1.0, float(np.clip((b - c) / a, 0, 1))
    return p1 + d1 * s, p2 + d2 * t


def axis_quaternion(axis):
    """Quaternion (x, y, z, w) taking +z onto the unit vector axis."""
    z = np.array([0.0, 0.0, 1.0])
    v, w = np.cross(z, axis), 1.0 + z @ axis
    q = np.array([v[0], v[1], v[2], w])
    return q / np.linalg.norm(q)


def capsule_case(rng):
    """A random capsule: (centre, unit axis, half segment, radius)."""
    axis = rng.normal(size=3)
    return rng.uniform(-1, 1, 3), axis / np.linalg.norm(axis), rng.uniform(0.05, 0.6), \
        rng.uniform(0.02, 0.2)


def test_capsule_capsule_matches_the_segments_closed_form():
    rng = np.random.default_rng(20261124)
    checked = 0
    for _ in range(300):
        (ca, ua, ha, ra), (cb, ub, hb, rb) = capsule_case(rng), capsule_case(rng)
        pa, pb = segment_closest(ca - ha * ua, ca + ha * ua, cb - hb * ub, cb + hb * ub)
        expected = float(np.linalg.norm(pa - pb)) - ra - rb
        if expected < 0.0:
            continue                      # overlapping: the depth has no such closed form
        checked += 1
        distance, on_a, on_b = _core.closest_points(
            Shape.capsule(ra, 2 * ha), ca, axis_quaternion(ua),
            Shape.capsule(rb, 2 * hb), cb, axis_quaternion(ub))
        assert distance == pytest.approx(expected, abs=TOL_M)
        assert np.linalg.norm(on_a - on_b) == pytest.approx(expected, abs=TOL_M)
    assert checked > 100


def test_capsules_parallel_crossing_and_overlapping():
    side = Shape.capsule(0.1, 1.0)
    # parallel, 0.5 apart: 0.5 - 0.2
    assert _core.closest_points(side, (0, 0, 0), IDENTITY, side, (0.5, 0, 0.3), IDENTITY)[0] \
        == pytest.approx(0.3, abs=TOL_M)
    # crossing at right angles, 0.4 apart along y
    across = axis_quaternion(np.array([1.0, 0.0, 0.0]))
    assert _core.closest_points(side, (0, 0, 0), IDENTITY, side, (0, 0.4, 0), across)[0] \
        == pytest.approx(0.2, abs=TOL_M)
    # collinear, overlapping by 0.05 at the spherical ends: depth 0.05
    assert _core.closest_points(side, (0, 0, 0), IDENTITY, side, (0, 0, 1.15), IDENTITY)[0] \
        == pytest.approx(-0.05, abs=1e-4)


def test_world_objects_operator_body_against_a_link_box(world):
    # the operator's body: a 1.3 m cylinder of radius 0.2 standing on the floor
    world.add_cylinder(1, 0.2, 1.3, (0, 0, 0.65), IDENTITY, GREY, _core.GROUP_DYNAMIC)
    world.add_box(2, (0.1, 0.3, 0.05), (0.9, 0.4, 1.0), IDENTITY, GREY, _core.GROUP_ROBOT)
    distance, on_body, on_box = world.closest_points(1, 2)
    # the box's nearest corner edge is at (0.8, 0.1) in the plane, inside the body's height
    assert distance == pytest.approx(math.hypot(0.8, 0.1) - 0.2, abs=TOL_M)
    assert on_box[0] == pytest.approx(0.8, abs=TOL_M) and on_box[1] == pytest.approx(0.1,
                                                                                     abs=TOL_M)
    assert 0.95 - TOL_M <= on_box[2] <= 1.05 + TOL_M
    with pytest.raises(KeyError):
        world.closest_points(1, 99)


def test_minimum_distances_per_group_by_handle_and_by_shape(world):
    world.add_cylinder(1, 0.2, 1.3, (0, 0, 0.65), IDENTITY, GREY, _core.GROUP_DYNAMIC)
    world.add_sphere(2, 0.11, (0, 0, 1.41), IDENTITY, GREY, _core.GROUP_DYNAMIC)   # head
    world.add_sphere(10, 0.05, (1.0, 0, 0.5), IDENTITY, GREY)       # group 0: two links
    world.add_box(11, (0.05, 0.05, 0.05), (0.0, 0.7, 1.45), IDENTITY, GREY)
    world.add_sphere(12, 0.05, (-2.0, 0, 0.5), IDENTITY, GREY)      # group 2
    d, pa, pb, index_a, handle_b = world.minimum_distances([1, 2], [10, 11, 12], [0, 0, 2], 3)
    # box 11 is nearer the body's top rim (0.45 across, 0.1 up) than the head (0.65 - 0.11)
    assert d[0] == pytest.approx(math.hypot(0.45, 0.1), abs=TOL_M)
    assert index_a[0] == 0 and handle_b[0] == 11
    assert math.isinf(d[1]) and index_a[1] == -1 and handle_b[1] == -1
    assert d[2] == pytest.approx(2.0 - 0.05 - 0.2, abs=TOL_M) and handle_b[2] == 12
    assert np.linalg.norm(pa[2] - pb[2]) == pytest.approx(d[2], abs=TOL_M)
    # the same body given by value, moved 0.5 m towards +x (a tracker's estimate)
    shapes = [Shape.cylinder(0.2, 1.3), Shape.sphere(0.11)]
    d2, *_ = world.minimum_distances_to(shapes, [[0.5, 0, 0.65], [0.5, 0, 1.41]],
                                        [IDENTITY, IDENTITY], [10, 11, 12], [0, 0, 2], 3)
    assert d2[0] == pytest.approx(0.5 - 0.05 - 0.2, abs=TOL_M)
    assert d2[2] == pytest.approx(2.5 - 0.05 - 0.2, abs=TOL_M)


def test_bad_queries_are_refused(world):
    world.add_sphere(1, 0.1, (0, 0, 0), IDENTITY, GREY)
    with pytest.raises(ValueError, match="group_of_b"):
        world.minimum_distances([1], [1], [3], 2)
    with pytest.raises(ValueError, match="same length"):
        world.minimum_distances([1], [1], [0, 0], 2)
    with pytest.raises(KeyError):
        world.minimum_distances([5], [1], [0], 1)
    with pytest.raises(ValueError, match="radius"):
        Shape.sphere(-1.0)
    with pytest.raises(ValueError, match="radius"):
        Shape.capsule(math.nan, 0.1)
    with pytest.raises(ValueError):
        _core.closest_points(Shape.sphere(0.1), (math.nan, 0, 0), IDENTITY,
                             Shape.sphere(0.1), (0, 0, 0), IDENTITY)
