# Shared fixtures: the repository root, the bundled lab map, its caster and config, and one
# short simulated lab tour (session-wide: loading and simulating once keeps the suite fast).
import os
import pathlib

import pytest

import polyloc

ROOT = pathlib.Path(os.environ.get("POLYLOC_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[3]))


@pytest.fixture(scope="session")
def root():
    return ROOT


@pytest.fixture(scope="session")
def lab_mesh():
    return polyloc.load_mesh(str(ROOT / "maps/lab.obj"))


@pytest.fixture(scope="session")
def lab_caster(lab_mesh):
    return polyloc.EmbreeCaster(lab_mesh, threads=2)


@pytest.fixture(scope="session")
def lab_config():
    return polyloc.load_config(str(ROOT / "maps/config/lab.yaml"))


@pytest.fixture(scope="session")
def lab_run():
    """The first 8 s of the lab tour (1 s standing, then east along the corridor)."""
    return polyloc.simulate(str(ROOT / "maps/scenarios/lab_tour.yaml"), duration=8.0)
