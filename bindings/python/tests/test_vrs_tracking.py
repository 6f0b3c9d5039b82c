import numpy as np
import pytest

import polyloc

CORRIDOR_WALL = 3.5 - 0.075  # y of the corridor wall's south face
WEST_WALL = 0.075            # x of the west wall's inner face


def first_second(lab_run):
    return [f for f in lab_run.frames if f.t <= 1.0]  # the robot stands at its start


def test_vrs_sees_the_walls_around_the_start(lab_config, lab_run, lab_mesh):
    vrs = polyloc.VirtualRangeScanner(lab_config.rig, lab_config.robot, lab_config.vrs, map=lab_mesh)
    frames = first_second(lab_run)
    for f in frames:
        assert vrs.add_frame(f.sensor, f.stamp_ns, f.map_T_base, f.measured)
    pose = frames[-1].map_T_base
    scan = vrs.update(frames[-1].stamp_ns, pose)
    assert scan.ranges.shape == (720,) and scan.angle_increment == pytest.approx(np.radians(0.5))
    a, r = scan.angles, scan.ranges
    left = np.abs(a - np.pi / 2) < np.radians(10)
    behind = np.abs(np.abs(a) - np.pi) < np.radians(10)
    # Perpendicular distances to the walls, medians over the segments (S300 noise is 3 cm).
    assert np.median(r[left] * np.sin(a[left])) == pytest.approx(CORRIDOR_WALL - pose.y, abs=0.02)
    assert np.median(-r[behind] * np.cos(a[behind])) == pytest.approx(pose.x - WEST_WALL, abs=0.02)
    assert np.mean(scan.source[left] & 1) > 0.9  # direct sources (a dropout leaves a segment empty)
    assert vrs.counters["frames"] == len(frames) and vrs.counters["updates"] == 1
    assert not vrs.add_frame(0, frames[-1].stamp_ns, pose, np.ones(3))  # wrong size: counted
    assert vrs.counters["frames_rejected"] == 1


def test_people_tracker_takes_level_scans(lab_config, lab_run):
    people = polyloc.PeopleTracker(lab_config.rig, lab_config.tracking)
    assert people.sensors == [0, 1]  # the two S300s named in lab.yaml
    frames = first_second(lab_run)
    results = {people.add_scan(f.sensor, f.stamp_ns, f.map_T_sensor, f.measured) for f in frames}
    people.flush()
    assert results == {"ok"}
    tracks = people.tracks()
    assert len(tracks["id"]) == 0 and tracks["position"].shape == (0, 2)  # nobody near the start
    c = people.counters
    assert c["scans"] == sum(f.sensor in (0, 1) for f in frames) and c["ignored"] > 0
    assert people.add_scan(0, frames[-1].stamp_ns + 10 ** 8, frames[0].map_T_sensor, np.ones(3)) == "wrong number of ranges"
    with pytest.raises(ValueError, match="urg_front"):
        cfg = polyloc.TrackingConfig()
        cfg.sensors = ["urg_front"]  # tilted: cannot track
        polyloc.PeopleTracker(lab_config.rig, cfg)
