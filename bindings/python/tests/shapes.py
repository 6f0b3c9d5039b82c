# Meshes built in code for the tests.
import numpy as np

import polyloc


def unit_cube(size=1.0):
    """A closed box [0, size]^3, triangles counter-clockwise seen from outside."""
    v = np.array([[x, y, z] for z in (0, size) for y in (0, size) for x in (0, size)], dtype=np.float32)
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    tris = [t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))]
    return polyloc.Mesh(v, np.array(tris), labels=np.ones(len(tris)), label_names=["", "box"])
