"""Screenshots through the command line's offscreen renderer, and the README's Python example as written."""
import os
import re
import struct
import subprocess
import sys

import numpy as np
import pytest

import sculpt
from conftest import SOURCE_DIR, icosphere, run_cli, write_obj


def png_size(path):
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and data[12:16] == b"IHDR"
    return struct.unpack(">II", data[16:24])


def test_screenshot_writes_a_png_of_the_asked_size(tmp_path):
    V, F = icosphere(2)
    session = sculpt.Session(V, F)
    session.drag_vertex(0, (V[0] * 1.3).tolist())
    path = tmp_path / "shot.png"
    session.screenshot(str(path), size=(320, 200), camera=(30, 20, 4.0), overlays=["lattice", "wireframe"])
    assert png_size(path) == (320, 200)
    session.screenshot(str(path))
    assert png_size(path) == (1280, 800)


def test_screenshot_is_the_command_lines_picture(cli, tmp_path):
    V, F = icosphere(2)
    mesh = tmp_path / "sphere.obj"
    write_obj(mesh, V, F)
    op = {"op": "drag_vertex", "vertex": 0, "target": (V[0] * 1.3).tolist()}
    cli_png = tmp_path / "cli.png"
    done, _, _ = run_cli(tmp_path, {"ops": [op]}, mesh,
                         ["--screenshot", str(cli_png), "--size", "200x120", "--overlay", "jacobian"])
    assert done.returncode == 0, done.stderr
    session = sculpt.load(str(mesh), track_jacobian=True)
    session.run(op)
    module_png = tmp_path / "module.png"
    session.screenshot(str(module_png), size=(200, 120), overlays=["jacobian"])
    assert module_png.read_bytes() == cli_png.read_bytes()


def test_screenshot_options_are_checked(tmp_path):
    V, F = icosphere(1)
    session = sculpt.Session(V, F)
    with pytest.raises(sculpt.Error, match=r"size: expected \(width, height\)"):
        session.screenshot(str(tmp_path / "a.png"), size=(0, 10))
    with pytest.raises(sculpt.Error, match=r"camera: expected \(yaw, pitch, distance\)"):
        session.screenshot(str(tmp_path / "a.png"), camera=(0, 0, -1))
    with pytest.raises(sculpt.Error, match=r"overlays: each must be"):
        session.screenshot(str(tmp_path / "a.png"), overlays=["normals"])
    with pytest.raises(sculpt.Error, match=r"screenshot: "):
        session.screenshot(str(tmp_path / "no" / "folder" / "a.png"), size=(8, 8))
    assert not (tmp_path / "a.png").exists()


def test_the_readme_example_runs_as_written(tmp_path):
    """The README's Python section: five lines that deform a mesh (run from the source folder, output moved to
    a temporary folder)."""
    readme = (SOURCE_DIR / "README.md").read_text()
    section = readme[readme.index("## Python"):]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    assert len([line for line in code.splitlines() if line.strip()]) == 5
    code = code.replace("out/", str(tmp_path) + "/")
    env = dict(os.environ, PYTHONPATH=os.path.dirname(os.path.abspath(sculpt.__file__)))
    done = subprocess.run([sys.executable, "-c", code], cwd=SOURCE_DIR, env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "deformed.obj").exists()
    assert png_size(tmp_path / "deformed.png") == (1280, 800)
