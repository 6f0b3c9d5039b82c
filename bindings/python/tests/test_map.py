import numpy as np
import pytest

import polyloc
from shapes import unit_cube


def test_lab_map_as_documented(lab_mesh):
    # docs/maps.md: about 6,800 triangles; bounds (-0.4, -0.4, -3.2) .. (26.4, 14.4, 2.8).
    assert 6000 < lab_mesh.num_triangles < 7500
    np.testing.assert_allclose(lab_mesh.bounds, [[-0.4, -0.4, -3.2], [26.4, 14.4, 2.8]], atol=1e-4)
    for label in ("floor", "wall", "glass", "door", "table", "chair", "danger", "ramp"):
        assert lab_mesh.find_label(label) > 0, label
    assert lab_mesh.find_label("no such label") == -1


def test_arrays_are_read_only_views(lab_mesh):
    v, t, l = lab_mesh.vertices, lab_mesh.triangles, lab_mesh.labels
    assert v.shape == (lab_mesh.num_vertices, 3) and v.dtype == np.float32
    assert t.shape == (lab_mesh.num_triangles, 3) and t.dtype == np.uint32
    assert l.shape == (lab_mesh.num_triangles,) and int(l.max()) < len(lab_mesh.label_names)
    assert not v.flags.writeable and not v.flags.owndata  # the mesh's memory, not a copy
    with pytest.raises(ValueError):
        v[0, 0] = 1.0
    assert lab_mesh.label_of(0) == lab_mesh.label_names[l[0]]


def test_validation_of_lab_and_cube(lab_mesh):
    # docs/maps.md: the lab reports 0 open, 0 non-manifold and 0 inconsistent edges.
    r = polyloc.validate_mesh(lab_mesh)
    assert (r.open_edges, r.non_manifold_edges, r.inconsistent_edges) == (0, 0, 0)
    assert r.closed and r.consistent_winding and r.triangles == lab_mesh.num_triangles
    assert sum(r.label_counts.values()) == r.triangles
    cube = unit_cube()
    assert polyloc.validate_mesh(cube).closed
    np.testing.assert_allclose(cube.normals()[0], [0, 0, -1])  # bottom face points down
    open_box = polyloc.Mesh(cube.vertices, cube.triangles[2:])
    assert polyloc.validate_mesh(open_box).open_edges == 4


def test_slice_of_cube():
    s = polyloc.slice_mesh(unit_cube(2.0), 1.0)
    assert s["a"].shape == s["b"].shape and s["a"].shape[1] == 2
    pts = np.vstack([s["a"], s["b"]])
    assert len(s["triangle"]) == 8  # two triangles per side wall
    np.testing.assert_allclose(pts.min(axis=0), [0, 0], atol=1e-6)
    np.testing.assert_allclose(pts.max(axis=0), [2, 2], atol=1e-6)


def test_save_and_load_round_trip(tmp_path):
    path = str(tmp_path / "cube.obj")
    polyloc.save_mesh(unit_cube(), path)
    back = polyloc.load_mesh(path, scale=2.0)
    np.testing.assert_allclose(back.bounds, [[0, 0, 0], [2, 2, 2]])
    assert "box" in back.label_names


def test_load_errors(tmp_path):
    with pytest.raises(FileNotFoundError, match="load_mesh: no such file"):
        polyloc.load_mesh(str(tmp_path / "missing.obj"))
    bad = tmp_path / "bad.ply"
    bad.write_bytes(b"ply\nformat binary_little_endian 1.0\nelement vertex 99\nend_header\n\x01\x02")
    with pytest.raises(polyloc.MapError, match="bad.ply"):
        polyloc.load_mesh(str(bad))
    assert issubclass(polyloc.MapError, OSError)
    with pytest.raises(ValueError, match="scale must be positive"):
        polyloc.load_mesh(str(bad), scale=0)
    with pytest.raises(polyloc.MapError, match="up"):
        polyloc.load_mesh(str(bad), up_axis="w")
    with pytest.raises(ValueError, match=r"vertices: expected shape \(N, 3\)"):
        polyloc.Mesh(np.zeros((3, 2)), np.zeros((1, 3)))
    with pytest.raises(ValueError, match="refers to vertex 7"):
        polyloc.Mesh(np.zeros((3, 3)), np.array([[0, 1, 7]]))
