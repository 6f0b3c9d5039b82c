import pytest

import polyloc


def test_sections_are_settings_structs(lab_config):
    assert lab_config.map_file.endswith("maps/lab.obj") and lab_config.map_scale == 1.0
    assert lab_config.vrs.range_max == 8.0 and lab_config.tracking.sensors == ["s300_front_left", "s300_rear_right"]
    assert lab_config.depth_filter.smoothing.method == "median"
    m = polyloc.MclConfig.from_yaml("particles: 300\nbeam: {sigma_hit: 0.1}")
    assert (m.particles, m.beam.sigma_hit, m.dof) == (300, 0.1, 3)


def test_config_errors_name_file_line_and_key(root, tmp_path):
    with pytest.raises(FileNotFoundError, match="load_config: no such file"):
        polyloc.load_config(str(tmp_path / "none.yaml"))
    bad = tmp_path / "bad.yaml"
    bad.write_text(f"map: {root}/maps/lab.obj\nrig: lisa\nmcl:\n  partcles: 10\n")
    with pytest.raises(polyloc.ConfigError, match=r"bad.yaml:4:\d+: .*mcl.partcles") as e:
        polyloc.load_config(str(bad))
    assert isinstance(e.value, ValueError)
    with pytest.raises(ValueError, match="particles"):
        polyloc.MclConfig.from_yaml("particles: many")
