import math

import numpy as np
import pytest

import polyloc


def test_collected_run(lab_run, lab_config):
    assert lab_run.duration == 8.0 and lab_run.rig.names == lab_config.rig.names
    assert len(lab_run.stamps) == 401  # odometry at 50 Hz, both ends
    stamps = [s for kind, s, _ in lab_run.events()]
    assert stamps == sorted(stamps) and len(stamps) == len(lab_run.stamps) + len(lab_run.frames)
    first = lab_run.truth[0]
    assert (first.x, first.y) == pytest.approx((1.3, 1.75), abs=1e-3)  # the route's first waypoint
    f = lab_run.frames[0]
    assert f.sensor == 0 and f.exact.dtype == np.float32 and f.measured.shape == (541,)
    assert f.map_T_sensor.is_approx(lab_config.rig[0].world_pose(f.map_T_base), 1e-9)
    assert not f.exact.flags.writeable  # a view of the frame's own memory


def test_exact_ranges_match_the_map(lab_run, lab_caster, lab_config):
    # urg_front while driving along the corridor; the simulator's map has two chairs moved in
    # lab 2, far from here, and people: compare where the truth hit the map (label != 0).
    frame = next(f for f in lab_run.frames if f.sensor == 2 and f.t > 3)
    expected = lab_caster.scan(lab_config.rig[2], frame.map_T_base)[0]
    hit = np.isfinite(expected) & np.isfinite(frame.exact) & (frame.label != 0)
    assert hit.mean() > 0.5
    np.testing.assert_allclose(frame.exact[hit], expected[hit], atol=1e-3)


def test_run_to_mcap_and_read_back(root, tmp_path):
    path = str(tmp_path / "tour.mcap")
    sim = polyloc.Simulator(polyloc.load_scenario(str(root / "maps/scenarios/lab_tour.yaml"), duration=2.0))
    progress = []
    summary = sim.run(path, on_progress=progress.append)
    assert progress[-1] == pytest.approx(1.0)
    assert summary["topics"]["/scan/s300_front_left"] == 26  # 12.5 Hz over 2 s, both ends
    with polyloc.open_recording(path) as rec:
        assert rec.format == "mcap"
        topics = {t["name"]: t for t in rec.topics()}
        assert topics["/odom"]["type"] == "nav_msgs/msg/Odometry" and topics["/odom"]["count"] == 101
        seen = {}
        for topic, log_ns, msg in rec:
            seen.setdefault(topic, msg)
        assert rec.stats()["messages"] == summary["messages"] and rec.stats()["rejected"] == 0
    scan = seen["/scan/s300_front_left"]
    assert scan["type"] == "sensor_msgs/msg/LaserScan" and scan["ranges"].shape == (541,)
    assert scan["angle_min"] == pytest.approx(-math.radians(135))
    depth = seen["/depth/tof_front/image"]
    assert depth["image"].shape == (50, 64) and depth["image"].dtype == np.float32
    assert seen["/depth/tof_front/artefacts"]["image"].dtype == np.uint8
    assert seen["/depth/tof_front/camera_info"]["k"].shape == (3, 3)
    assert seen["/ground_truth"]["pose"].is_approx(sim.ground_truth(0.0), 1e-6)
    assert seen["/odom"]["covariance"].shape == (6, 6)
    assert len(seen["/tf_static"]["transforms"]) >= 7


def test_lidar_point_clouds(root, tmp_path):
    scenario = polyloc.load_scenario(str(root / "maps/scenarios/lab_tour.yaml"), duration=0.3)
    rig = polyloc.Rig()
    rig.name = "lidar_only"
    rig.add(polyloc.Sensor("vlp", polyloc.sensor_preset("vlp16"), polyloc.Pose(z=0.8)), "vlp16")
    scenario.config.rig = rig
    path = str(tmp_path / "lidar.mcap")
    polyloc.Simulator(scenario).run(path)
    clouds = [m for _, _, m in polyloc.open_recording(path, topics=["/points/vlp"])]
    assert len(clouds) == 4  # 10 Hz over 0.3 s, both ends
    pts = clouds[0]["points"]
    assert clouds[0]["fields"] == ["x", "y", "z", "intensity", "ring"]
    assert pts.dtype["x"] == np.float32 and pts["ring"].max() == 15


def test_callback_errors_reach_the_caller(root):
    sim = polyloc.Simulator(polyloc.load_scenario(str(root / "maps/scenarios/lab_tour.yaml"), duration=1.0))

    def boom(frame):
        raise KeyError("from the callback")

    with pytest.raises(KeyError, match="from the callback"):
        sim.run(on_frame=boom)
    with pytest.raises(RuntimeError, match="already running"):
        sim.run(on_tick=lambda *a: sim.run())
    assert sim.run()["messages"] > 0  # still usable


def test_scenario_and_recording_errors(root, tmp_path):
    with pytest.raises(FileNotFoundError, match="load_scenario"):
        polyloc.load_scenario(str(tmp_path / "none.yaml"))
    bad = tmp_path / "bad.yaml"
    bad.write_text(f"config: {root}/maps/config/lab.yaml\nroute:\n  waypoints: [[1, 1], [2, 1]]\n  speed_limit: 3\n")
    with pytest.raises(polyloc.ConfigError, match=r"bad.yaml:4:.*speed_limit"):
        polyloc.load_scenario(str(bad))
    with pytest.raises(ValueError, match="duration must be positive"):
        polyloc.load_scenario(str(root / "maps/scenarios/lab_tour.yaml"), duration=-1)
    with pytest.raises(FileNotFoundError, match="open_recording"):
        polyloc.open_recording(str(tmp_path / "none.mcap"))
    text = tmp_path / "notes.txt"
    text.write_text("not a recording\n")
    with pytest.raises(polyloc.RecordingError, match="notes.txt"):
        polyloc.open_recording(str(text))
