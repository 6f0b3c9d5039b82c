# Ranges against geometry known from the map's generator (maps/generator/lab.cpp, docs/maps.md):
# walls 0.15 m thick on their centre lines, the corridor wall at y = 3.5, the west wall at x = 0,
# the floor top at z = 0. The robot's start in the corridor is (1.3, 1.75).
import math

import numpy as np
import pytest

import polyloc
from shapes import unit_cube

HALF_WALL = 0.075


def test_rays_against_known_walls(lab_caster, lab_mesh):
    origin = np.array([3.0, 1.75, 1.5])
    dirs = np.array([[0, 1, 0], [-1, 0, 0], [0, 0, -1], [0, 0, 1]], dtype=np.float32)
    r = lab_caster.cast(origin, dirs)
    assert r.dtype == np.float32 and r.shape == (4,)
    np.testing.assert_allclose(r[:3], [3.5 - HALF_WALL - 1.75, 3.0 - HALF_WALL, 1.5], atol=1e-4)
    assert math.isinf(r[3])  # no ceiling
    hits = lab_caster.cast(origin, dirs, hits=True)
    names = [lab_mesh.label_names[l] for l in hits["label"][:3]]
    assert names == ["wall", "wall", "floor"]
    np.testing.assert_allclose(hits["normal"][0], [0, -1, 0], atol=1e-5)  # faces the corridor
    assert hits["triangle"][3] == 0xFFFFFFFF and hits["label"][3] == 0


def test_windows_and_diagonal(lab_caster):
    origin = np.array([[3.0, 1.75, 1.5]])
    up = np.array([[0, 1.0, 0]])
    assert math.isinf(lab_caster.cast(origin, up, tmax=1.0)[0])          # wall beyond the window
    assert lab_caster.cast(origin, up, tmin=0.5)[0] == pytest.approx(1.675, abs=1e-4)
    d = np.array([[0, math.sqrt(0.5), -math.sqrt(0.5)]])                # 45 deg down towards the wall
    assert lab_caster.cast(origin, d)[0] == pytest.approx(1.5 * math.sqrt(2), abs=1e-4)  # floor first


def test_scans_are_poses_times_beams(lab_caster, lab_config):
    sensor = lab_config.rig["s300_front_left"]
    beams = sensor.beams()
    base = [polyloc.Pose.planar(3.0, 1.75, 0.0), polyloc.Pose.planar(8.0, 2.0, 1.0)]
    world = np.stack([sensor.world_pose(p).matrix() for p in base])
    scans = lab_caster.cast_scans(world, beams)
    assert scans.shape == (2, len(beams)) and scans.dtype == np.float32
    np.testing.assert_array_equal(scans, lab_caster.scan(sensor, base))
    # The same rays one by one give the same ranges.
    p = sensor.world_pose(base[1])
    dirs = beams.directions @ p.matrix()[:3, :3].T
    explicit = lab_caster.cast(p.translation, dirs, tmin=beams.range_min, tmax=beams.range_max)
    np.testing.assert_allclose(scans[1], explicit, rtol=1e-5)


def test_inside_solid_and_free_space():
    cube = polyloc.EmbreeCaster(unit_cube(2.0), threads=1)
    dirs = np.array([[1.0, 0, 0], [-1.0, 0, 0]])
    np.testing.assert_allclose(cube.cast([-1.0, 1, 1], dirs), [1.0, np.inf])
    assert cube.cast([1.0, 1, 1], dirs).tolist() == [0.0, 0.0]  # starts inside: range 0
    cube.backface_is_solid = False
    assert cube.cast([1.0, 1, 1], dirs).tolist() == [1.0, 1.0]
    free = cube.query_free(np.array([[1, 1, 1], [3, 1, 1], [2.1, 1, 1]]), clearance=0.2)
    assert free.dtype == bool and free.tolist() == [False, True, False]


def test_bad_ray_input(lab_caster):
    with pytest.raises(ValueError, match=r"origins: expected shape \(2, 3\), got \(2, 2\)"):
        lab_caster.cast(np.zeros((2, 2)), np.eye(3)[:2])
    with pytest.raises(ValueError, match=r"directions: expected shape \(N, 3\), got \(3,\)"):
        lab_caster.cast(np.zeros(3), np.array([1.0, 0, 0]))
    with pytest.raises(TypeError, match="directions: expected a numeric array"):
        lab_caster.cast(np.zeros(3), np.array([["x", "y", "z"]]))
    with pytest.raises(ValueError, match="row 0 has length 2"):
        lab_caster.cast(np.zeros(3), np.array([[2.0, 0, 0]]))
    with pytest.raises(ValueError, match=r"window_min: expected shape \(541,\)"):
        lab_caster.cast_scans(polyloc.Pose(), polyloc.sensor_preset("sick_s300").beams(), window_min=np.zeros(3))
