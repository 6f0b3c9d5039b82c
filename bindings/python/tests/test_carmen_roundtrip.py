"""bench/carmen_roundtrip.sh on 20 s of the office patrol: a simulated run written as a corrected
CARMEN log (bench/carmen_from_run.py, through this module's recording reader), mapped and
extruded by `polyloc map extrude --carmen`, and another run localised on the extruded map."""
import json
import os
import pathlib
import subprocess
import sys

import pytest

import polyloc


def cli_candidates():
    """Where the polyloc CLI may be: $POLYLOC_BIN_DIR, then build/bin beside this module's build."""
    bins = [pathlib.Path(os.environ["POLYLOC_BIN_DIR"])] if "POLYLOC_BIN_DIR" in os.environ else []
    bins.append(pathlib.Path(polyloc.__file__).resolve().parents[2] / "bin")
    return [b / "polyloc" for b in bins]


def build_dir():
    """The build tree of this module (build/python/polyloc -> build), if it has the CLI."""
    return next((p.parent.parent for p in cli_candidates() if p.exists()), None)


def test_carmen_log_to_map_and_back(root, tmp_path):
    build = build_dir()
    if build is None:   # a failure, not a skip: a missing binary must not pass as a green suite
        pytest.fail("the polyloc CLI is not built: no " + " or ".join(map(str, cli_candidates()))
                    + " (cmake --build build --target polyloc, or set POLYLOC_BIN_DIR)")
    env = dict(os.environ, PYTHONPATH=str(pathlib.Path(polyloc.__file__).resolve().parents[1]))
    done = subprocess.run(["bash", "bench/carmen_roundtrip.sh", str(build), "20", str(tmp_path), sys.executable],
                          cwd=root, env=env, capture_output=True, text=True, timeout=240)
    assert done.returncode == 0, done.stderr
    j = json.loads(done.stdout.strip().splitlines()[-1])
    # 20 s at 75 Hz, two scanners, every scan has its pose.
    assert j["scans_used"] == 2 * 1500 + 2 and j["scans_skipped"] == 0, j
    assert j["closed"] and j["triangles"] > 100, j
    # On the map made from the other run: a few centimetres (5 cm cells); on the mesh: millimetres.
    assert j["extruded"]["ate_rmse_m"] < 0.06 and j["extruded"]["yaw_rmse_deg"] < 1.0, j
    assert j["original"]["ate_rmse_m"] < 0.01, j
    assert j["extruded"]["updates"] > 100
    grid = tmp_path / "grid.pgm"
    assert grid.exists() and (tmp_path / "extruded_localize.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
