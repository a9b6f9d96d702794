"""The operator tracker's parts (no master): the blob cameras' rays and triangulation through
the thesis's calibration, the laser's background and person clusters, the Kalman filter."""
import math

import numpy as np
import pytest

from epuck_vrep_compat.nodes import tracker_geometry as geo
from epuck_vrep_compat.nodes.tracker_filter import OperatorFilter, published_covariance


def project(camera, point):
    """(u, v) of a world point (V-REP vision sensor convention)."""
    local = camera.rotation.T @ (np.asarray(point) - camera.centre)
    return 0.5 - camera.focal * local[0] / local[2], 0.5 + camera.focal * local[1] / local[2]


@pytest.mark.parametrize("point", [(0.4, 1.2, 0.6), (-0.5, 0.8, 0.6), (1.0, 2.0, 0.9)])
def test_two_cameras_triangulate_and_one_cuts_its_ray_at_the_height(point):
    cams = [geo.BlobCamera(m) for m in geo.THESIS_CAMERA_MATRICES]
    uv = [project(c, point) for c in cams]
    found = geo.triangulate([c.centre for c in cams], [c.ray(*p) for c, p in zip(cams, uv)])
    np.testing.assert_allclose(found, point, atol=1e-9)
    np.testing.assert_allclose(cams[0].at_height(*uv[0], point[2]), point[:2], atol=1e-9)
    assert geo.triangulate([cams[0].centre] * 2, [cams[0].ray(*uv[0])] * 2) is None


def test_the_background_hides_what_never_moves_and_a_person_is_one_centre():
    angles = np.linspace(-0.5, 0.5, 201)
    wall = np.full(angles.size, 4.0)
    bg = geo.LaserBackground()
    assert np.isinf(bg.foreground(wall)).all()             # the first scan: all background
    person = wall.copy()
    centre = np.array([2.0, 0.3])
    for i, a in enumerate(angles):                       # a cylinder of r 0.2 at centre
        d = np.array([math.cos(a), math.sin(a)])
        b = d @ centre
        disc = b * b - (centre @ centre - 0.04)
        if disc >= 0:
            person[i] = b - math.sqrt(disc)
    front = bg.foreground(person)
    points = geo.scan_points(front, -0.5, angles[1] - angles[0], np.zeros(3),
                             (0.0, 0.0, 0.0, 1.0))
    found = geo.person_candidates(points, (0.0, 0.0))
    assert len(found) == 1 and np.linalg.norm(found[0] - centre) < 0.05
    best, d = geo.nearest(found, np.array([2.5, 0.3]), 0.8)
    assert best is found[0] and d < 0.6
    assert geo.nearest(found, np.array([4.0, 0.3]), 0.8)[0] is None


def test_the_filter_follows_a_walk_and_refuses_an_outlier():
    f = OperatorFilter(accel_density=4.0)
    r = np.eye(2) * 0.01 ** 2
    f.start(0.0, np.zeros(2), r)
    for k in range(1, 60):
        t = 0.05 * k
        f.predict(t)
        assert f.update(np.array([1.6 * t, 0.0]), r)
    assert f.x[2] == pytest.approx(1.6, abs=1e-3) and abs(f.x[3]) < 1e-9
    before = f.P.trace()
    assert not f.update(np.array([f.x[0] + 3.0, 0.0]), r)     # 3 m off: refused
    f.predict(f.t + 1.0)
    assert f.P.trace() > before                               # no measurement: grows


def test_the_kinect_ranges_him_along_its_ray_and_sees_occlusion():
    from epuck_vrep_compat.nodes.tracker_kinect import BODY_CENTRE_M, KinectRange
    from epuck_vrep_compat.geometry.transforms import quat_from_axis_angle, quat_mul
    kinect = KinectRange(57.0)
    # a sensor at 1 m height looking along world +x (its z): y rotation by +90 deg about y
    # maps z to x; then its x (image left) must be world +y: roll about x by -90 deg
    quat = quat_mul(quat_from_axis_angle((0, 1, 0), math.pi / 2),
                    quat_from_axis_angle((0, 0, 1), math.pi / 2))
    position = np.array([0.0, 0.0, 1.0])
    truth = np.array([3.0, 0.4])
    local_z = truth[0] - 0.2                       # his front surface, along the axis
    depth = np.full((480, 640), local_z, dtype=np.float32)
    estimate = truth + (0.0, 0.1)
    xy, cov = kinect.measurement(depth, position, quat, estimate)
    ray = estimate / np.linalg.norm(estimate)      # the ray through the estimate
    assert abs((xy - truth) @ ray) < 0.05          # the range is right ...
    assert (ray @ cov @ ray) < 0.01 and np.trace(cov) > 1.0   # ... and only the range counts
    assert BODY_CENTRE_M > 0
    depth[:] = 1.0                                 # something 1 m in front of the sensor
    assert kinect.measurement(depth, position, quat, truth) is None
    assert kinect.measurement(depth, position, quat, np.array([-3.0, 0.0])) is None  # behind


def test_the_published_covariance_adds_the_biases_and_the_lag_along_the_velocity():
    p = np.diag([0.01, 0.02, 0.5, 0.5])
    x = np.array([1.0, 2.0, 1.0, 0.0])
    cov = published_covariance(p, x, bias_sigma_m=0.05, lag_s=0.1)
    assert cov == pytest.approx(np.array([[0.01 + 0.0025 + 0.01, 0.0], [0.0, 0.02 + 0.0025]]))
    assert published_covariance(p, x) == pytest.approx(p[:2, :2])
