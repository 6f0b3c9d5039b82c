import math
import pickle

import numpy as np
import pytest

import polyloc
from polyloc import Pose


def rotation(roll, pitch, yaw):
    cr, sr, cp, sp, cy, sy = (math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch),
                              math.cos(yaw), math.sin(yaw))
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return rz @ ry @ rx


def test_xyzrpy_matches_ros_convention():
    p = Pose(1.0, -2.0, 0.5, 0.1, -0.2, 2.5)
    m = p.matrix()
    assert m.shape == (4, 4) and m.dtype == np.float64
    np.testing.assert_allclose(m[:3, :3], rotation(0.1, -0.2, 2.5), atol=1e-12)
    np.testing.assert_allclose(m[:3, 3], [1.0, -2.0, 0.5])
    np.testing.assert_allclose(p.to_xyzrpy(), [1.0, -2.0, 0.5, 0.1, -0.2, 2.5], atol=1e-12)
    assert Pose.from_matrix(m).is_approx(p)


def test_compose_inverse_and_points():
    a, b = Pose(1, 2, 0, 0, 0, math.pi / 2), Pose.planar(1, 0, 0)
    ab = a * b
    np.testing.assert_allclose(ab.matrix(), a.matrix() @ b.matrix(), atol=1e-12)
    assert (ab * ab.inverse()).is_approx(Pose())
    np.testing.assert_allclose(a * np.array([1.0, 0, 0]), [1, 3, 0], atol=1e-12)
    pts = np.array([[1.0, 0, 0], [0, 1, 0]])
    np.testing.assert_allclose(a.transform(pts), [[1, 3, 0], [0, 2, 0]], atol=1e-12)


def test_quaternion_interpolate_and_pickle():
    p = Pose.from_quaternion([math.cos(0.5), 0, 0, math.sin(0.5)], [1, 2, 3])
    assert p.yaw == pytest.approx(1.0)
    np.testing.assert_allclose(p.translation, [1, 2, 3])
    half = Pose.interpolate(Pose(), p, 0.5)
    assert half.yaw == pytest.approx(0.5) and half.z == pytest.approx(1.5)
    assert pickle.loads(pickle.dumps(p)).is_approx(p)
    assert polyloc.wrap_angle(3 * math.pi) == pytest.approx(math.pi)
    assert polyloc.angle_diff(0.1, 2 * math.pi) == pytest.approx(0.1)


def test_bad_pose_input_raises():
    with pytest.raises(ValueError, match=r"matrix: expected shape \(4, 4\), got \(3, 3\)"):
        Pose.from_matrix(np.eye(3))
    with pytest.raises(TypeError, match="numeric"):
        Pose.from_matrix(np.array([["a"] * 4] * 4))
    with pytest.raises(TypeError, match="expected a Pose"):
        polyloc.Sensor("s", polyloc.sensor_preset("sick_s300"), mount="front")
