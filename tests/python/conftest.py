"""Shared helpers of the Python module's tests: test meshes, OBJ text, and the command line to compare with.

ctest sets PYTHONPATH (the module's folder), SCULPT_CLI (build/sculpt) and SCULPT_SOURCE_DIR; run by hand:
    PYTHONPATH=build/python SCULPT_CLI=build/sculpt python3 -m pytest tests/python
"""
import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

SOURCE_DIR = Path(os.environ.get("SCULPT_SOURCE_DIR", Path(__file__).resolve().parents[2]))
CLI = Path(os.environ.get("SCULPT_CLI", SOURCE_DIR / "build" / "sculpt"))

# Report fields that measure time: they differ between any two runs.
TIMING_FIELDS = {"wall_ms", "injectivity_ms", "triangle_check_ms"}


def icosphere(level):
    """A unit icosphere: (V: n x 3 float64, F: m x 3 int64), outward-facing, 10 * 4**level + 2 vertices."""
    t = (1.0 + 5.0 ** 0.5) / 2.0
    V = [[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t], [0, -1, -t], [0, 1, -t],
         [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]]
    F = [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6],
         [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10],
         [8, 6, 7], [9, 8, 1]]
    V = [np.array(v, float) / np.linalg.norm(v) for v in V]
    for _ in range(level):
        midpoints = {}

        def midpoint(a, b):
            key = (min(a, b), max(a, b))
            if key not in midpoints:
                m = V[a] + V[b]
                V.append(m / np.linalg.norm(m))
                midpoints[key] = len(V) - 1
            return midpoints[key]

        finer = []
        for a, b, c in F:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            finer += [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
        F = finer
    return np.array(V), np.array(F, dtype=np.int64)


def random_mesh(rng, level):
    """A bumpy icosphere of the given level at a random scale and place (the engine assumes no unit)."""
    V, F = icosphere(level)
    V = V * (1.0 + 0.08 * rng.standard_normal((len(V), 1)))
    scale = 10.0 ** rng.uniform(-2, 2)
    return V * scale + rng.uniform(-3, 3, 3) * scale, F


def write_obj(path, V, F):
    """OBJ text with every coordinate in Python's shortest round-trip form, so any reader gets the same doubles."""
    lines = ["v %r %r %r" % tuple(float(x) for x in v) for v in V]
    lines += ["f %d %d %d" % tuple(int(i) + 1 for i in f) for f in F]
    Path(path).write_text("\n".join(lines) + "\n")


def read_obj_positions(path):
    """The `v` lines of an OBJ as a #V x 3 float64 array."""
    rows = [line.split()[1:4] for line in Path(path).read_text().splitlines() if line.startswith("v ")]
    return np.array(rows, dtype=float)


def run_cli(tmp_path, script, mesh_path, extra=()):
    """Runs `sculpt --headless` on script (a dict) and mesh_path; returns (completed process, output OBJ, report)."""
    script_path = tmp_path / "ops.json"
    script_path.write_text(json.dumps(script))
    out, report = tmp_path / "cli_out.obj", tmp_path / "cli_report.json"
    done = subprocess.run([str(CLI), "--headless", "--input", str(mesh_path), "--script", str(script_path), "--output",
                           str(out), "--report", str(report), *extra], capture_output=True, text=True)
    return done, out, (json.loads(report.read_text()) if done.returncode == 0 else None)


def without_timings(report):
    return {k: v for k, v in report.items() if k not in TIMING_FIELDS and k != "index"}


@pytest.fixture(scope="session")
def cli():
    if not CLI.exists():
        pytest.skip(f"the command line {CLI} is not built")
    return CLI
