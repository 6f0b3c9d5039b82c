import numpy as np
import pytest

import polyloc

H, W = 50, 64  # PMD O3D100


def step_scene():
    """A wall 2 m ahead on the left half, 3 m on the right; one flying pixel on the edge (a depth
    between both, as a ToF pixel that sees both surfaces reports) and one outlier on the wall."""
    depth = np.full((H, W), 2.0, dtype=np.float32)
    depth[:, W // 2:] = 3.0
    depth[25, W // 2] = 2.5
    depth[10, 10] = 2.6
    return depth, np.full((H, W), 1000.0, dtype=np.float32)


def test_removes_injected_flying_pixel_and_outlier():
    f = polyloc.DepthFilter(polyloc.sensor_preset("pmd_o3d100"))
    depth, amplitude = step_scene()
    r = f.apply(depth, amplitude)
    names = polyloc.DEPTH_REJECT_NAMES
    assert names[r.reason[25, W // 2]] == "jump_edge"
    assert names[r.reason[10, 10]] == "confidence"
    assert not r.valid[25, W // 2] and not r.valid[10, 10]
    assert r.kept == H * W - 2 and r.counts["kept"] == r.kept  # both rims of the step stay
    assert np.isnan(r.depth[25, W // 2]) and r.depth[0, 0] == pytest.approx(2.0)
    # Kept pixels as base-frame points (camera at the origin, x forward): x is the depth.
    assert r.points.shape == (r.kept, 3) and r.pixel.shape == (r.kept,)
    left = r.pixel % W < W // 2
    np.testing.assert_allclose(r.points[left, 0], 2.0, atol=0.02)
    assert np.all(r.points[left, 1] > 0)  # the left half of the image is +y (left) in base_link


def test_stages_can_be_switched_off():
    cfg = polyloc.DepthFilterConfig()
    cfg.jump_edge.enabled = False
    cfg.confidence.enabled = False
    r = polyloc.DepthFilter(polyloc.sensor_preset("pmd_o3d100"), config=cfg).apply(step_scene()[0])
    assert r.valid.all()
    y = polyloc.DepthFilterConfig.from_yaml("jump_edge: {min_angle: 10}\nsmoothing: {method: none}")
    assert y.jump_edge.min_angle == pytest.approx(np.radians(10)) and y.smoothing.method == "none"


def test_simulated_flying_pixels_are_removed(lab_config, lab_run):
    # The simulator tags the flying pixels it makes (ARTEFACT_BITS); the filter must find them.
    camera = lab_config.rig["tof_front"]
    f = polyloc.DepthFilter(camera, lab_config.depth_filter)
    frames = [fr for fr in lab_run.frames if fr.sensor == lab_config.rig.find("tof_front")]
    factor = camera.spec.depth_factors()  # ranges along the ray -> depth along the optical axis
    results = f.apply_batch(np.stack([fr.measured.reshape(H, W) * factor for fr in frames]))
    flying = removed = clean = kept = 0
    for fr, r in zip(frames, results):
        a = fr.artefacts.reshape(H, W)
        fly = (a & polyloc.ARTEFACT_BITS["flying_pixel"]) != 0
        good = (a == 0) & np.isfinite(fr.measured.reshape(H, W))
        flying += fly.sum()
        removed += (~r.valid[fly]).sum()
        clean += good.sum()
        kept += r.valid[good].sum()
    assert flying > 1000
    assert removed / flying > 0.9 and kept / clean > 0.9, (removed / flying, kept / clean)


def test_bad_frames():
    f = polyloc.DepthFilter(polyloc.sensor_preset("pmd_o3d100"))
    with pytest.raises(ValueError, match=r"depth: expected shape \(50, 64\), got \(64, 50\)"):
        f.apply(np.ones((64, 50)))
    with pytest.raises(ValueError, match=r"amplitude: expected shape \(50, 64\)"):
        f.apply(np.ones((50, 64)), amplitude=np.ones(3))
    r = f.apply(np.full((50, 64), np.nan))  # no measurement anywhere: rejected pixels, no error
    assert r.kept == 0 and r.counts["no_measurement"] == 50 * 64
    with pytest.raises(ValueError, match="not a depth camera"):
        polyloc.DepthFilter(polyloc.rig_preset("lisa")[0])



def test_seven_scenes_folder_reads_as_a_recording(root):
    redkitchen = root.parent / "shared/data/rgbd/7scenes-redkitchen"
    if not redkitchen.is_dir():
        pytest.skip(f"{redkitchen} is not here")
    with polyloc.open_recording(str(redkitchen), topics=["/depth/camera/image", "/depth/camera/camera_info"]) as rec:
        assert rec.format == "7scenes"
        assert {t["name"]: t["count"] for t in rec.topics()}["/depth/camera/image"] == 1000
        _, stamp, info = next(rec)
        _, _, image = next(rec)
    assert stamp == 1_000_000_000  # no stamps in 7-Scenes: frame n at 1 s + n / 30 Hz
    k = info["k"]
    assert k[0, 0] == 585.0 and k[0, 2] == 320.0
    depth = image["image"]
    assert depth.shape == (480, 640) and depth.dtype == np.float32
    finite = depth[np.isfinite(depth)]
    assert 0.02 < np.isnan(depth).mean() < 0.3  # the README: 11 % missing on average
    assert 0.4 < np.median(finite) < 4.0 and finite.max() < 3.976  # metres, none above 3975 mm
    cam = polyloc.depth_camera_from_intrinsics(640, 480, k[0, 0], k[1, 1], k[0, 2], k[1, 2])
    assert cam.cx == pytest.approx(320.5) and cam.num_beams == 640 * 480
    with pytest.raises(ValueError, match="fx"):
        polyloc.depth_camera_from_intrinsics(640, 480, float("nan"), 585, 320, 240)
