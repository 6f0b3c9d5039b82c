import math

import numpy as np
import pytest

import polyloc


def errors(results):
    pos = np.array([math.hypot(e.pose.x - g.x, e.pose.y - g.y) for e, g in results])
    yaw = np.degrees([abs(polyloc.angle_diff(e.pose.yaw, g.yaw)) for e, g in results])
    return pos, yaw


def test_config_exposes_rig_and_mcl(lab_config):
    rig = lab_config.rig
    assert rig.name == "lisa" and len(rig) == 7
    assert rig.names[:2] == ["s300_front_left", "s300_rear_right"]
    assert [s.kind for s in rig].count("planar_scanner") == 6 and rig["tof_front"].kind == "depth_camera"
    assert rig["s300_front_left"].num_beams == 541 and rig["tof_front"].num_beams == 64 * 50
    assert rig[0].mount.z == pytest.approx(0.1)  # docs: S300s 10 cm above the floor
    mcl = lab_config.mcl
    assert (mcl.dof, mcl.particles, mcl.beams_per_scan, mcl.refine.enabled) == (3, 2000, 60, True)
    assert mcl.update_min_angle == pytest.approx(math.radians(3))  # degrees in YAML, radians here
    assert polyloc.settings_dict(mcl)["beam"]["sigma_hit"] == 0.05
    assert lab_config.robot.height == pytest.approx(1.2) and lab_config.robot.footprint.shape == (4, 2)


def test_tracks_the_simulated_tour_from_the_true_start(lab_config, lab_run):
    loc = polyloc.Localizer(lab_config)
    results = polyloc.replay(loc, lab_run)
    assert len(results) >= 40  # the robot moves ~3.5 m: an update every 5 cm or 3 deg
    pos, yaw = errors(results)
    assert pos.max() < 0.05 and yaw.max() < 2.0, (pos.max(), yaw.max())
    last = loc.estimate()
    assert last.status == "tracking" and last.updates == loc.counters["updates"]
    assert last.covariance.shape == (6, 6) and np.all(np.diag(last.covariance) >= 0)
    assert np.sqrt(last.covariance[0, 0]) < 0.1
    parts = loc.particles()
    assert set(parts) == {"x", "y", "z", "qw", "qx", "qy", "qz", "logw"}
    assert len(parts["x"]) == last.particles and parts["x"].dtype == np.float64
    assert abs(np.average(parts["x"], weights=np.exp(parts["logw"])) - last.pose.x) < 0.05
    c = loc.counters
    assert c["scans"] == len(lab_run.frames) and c["scans_rejected"] == 0 and c["odometry"] == len(lab_run.stamps)


def test_converges_from_an_offset_start(root, lab_run, lab_caster, lab_mesh):
    g = lab_run.truth[0]
    start = polyloc.Pose.planar(g.x + 0.15, g.y - 0.1, g.yaw + math.radians(4))
    cov = np.diag([0.2 ** 2, 0.2 ** 2, 0.02 ** 2, math.radians(1) ** 2, math.radians(1) ** 2, math.radians(8) ** 2])
    cfg = polyloc.load_config(str(root / "maps/config/lab.yaml"))
    cfg.mcl.seed = 7  # sections are read-write: set before they are passed on
    loc = polyloc.Localizer(lab_caster, lab_mesh, cfg.rig, cfg.mcl)  # the other constructor
    assert loc.config.seed == 7
    pos, yaw = errors(polyloc.replay(loc, lab_run, start=start, covariance=cov))
    assert pos[-20:].max() < 0.05 and yaw[-20:].max() < 2.0, (pos[-20:].max(), yaw[-20:].max())


def test_scan_input_checks(lab_config, lab_caster, lab_mesh):
    loc = polyloc.Localizer(lab_config, mesh=lab_mesh, caster=lab_caster)
    loc.init_pose((1.3, 1.75, 0, 0, 0, 0), stamp_ns=1)
    loc.add_odometry(1, np.eye(4))
    with pytest.raises(ValueError, match=r"ranges: expected 541 ranges \(one per beam\), got 10"):
        loc.add_scan(0, 2, np.ones(10, dtype=np.float32))
    with pytest.raises(ValueError, match="sensor 'front' is not in rig 'lisa'"):
        loc.add_scan("front", 2, np.ones(541))
    with pytest.raises(ValueError, match="sensor index 9 out of range"):
        loc.add_scan(9, 2, np.ones(541))
    with pytest.raises(TypeError, match="ranges: expected a numeric array"):
        loc.add_scan(0, 2, ["a"] * 541)
    with pytest.raises(ValueError, match=r"covariance: expected shape \(6, 6\)"):
        loc.init_pose(polyloc.Pose(), covariance=np.eye(3))
    nan_scan = np.full(541, np.nan, dtype=np.float32)  # invalid beams are data, not errors
    assert loc.add_scan("s300_front_left", 3, nan_scan) is False
    assert loc.counters["scans_rejected"] == 1  # all beams invalid: counted, not raised
