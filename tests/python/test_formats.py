"""Mesh files in every format through the module: what `sculpt.load` reads and `Session.save` writes is what the
command line reads (--input) and writes (--output) for the same script, byte for byte, in PLY, STL and glTF."""
import json
import subprocess

import numpy as np
import pytest

import sculpt
from conftest import CLI, random_mesh


@pytest.mark.parametrize("seed", [3, 17])
@pytest.mark.parametrize("extension", ["ply", "stl", "glb", "gltf"])
def test_files_in_any_format_match_the_command_line(tmp_path, cli, seed, extension):
    rng = np.random.default_rng(seed)
    V, F = random_mesh(rng, 2)
    # The mesh as a file of that format, written by the module from arrays.
    warnings = sculpt.Session(V, F).save(str(tmp_path / f"in.{extension}"))
    assert all(isinstance(w, str) for w in warnings)
    session = sculpt.load(str(tmp_path / f"in.{extension}"))
    loaded = session.positions.copy()
    # PLY, STL and glTF hold single precision: the file's positions are the arrays rounded to float.
    if extension == "stl":  # welded in order of first use by the facets
        assert len(loaded) == len(V)
        assert set(map(tuple, loaded)) == set(map(tuple, V.astype(np.float32).astype(float)))
    else:
        assert np.array_equal(loaded, V.astype(np.float32).astype(float))
    v = int(rng.integers(0, len(loaded)))
    size = float(np.ptp(loaded, axis=0).max())
    target = (loaded[v] + rng.standard_normal(3) * 0.05 * size).tolist()
    report = session.drag_vertex(v, target)
    assert report["status"] in ("applied", "subdivided")
    session.save(str(tmp_path / f"py_out.{extension}"))
    script = tmp_path / "ops.json"
    script.write_text(json.dumps({"ops": [{"op": "drag_vertex", "vertex": v, "target": target}]}))
    done = subprocess.run([str(CLI), "--headless", "--input", str(tmp_path / f"in.{extension}"), "--script", str(script),
                           "--output", str(tmp_path / f"cli_out.{extension}")], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert (tmp_path / f"py_out.{extension}").read_bytes() == (tmp_path / f"cli_out.{extension}").read_bytes()


def test_bad_files_raise_with_the_readers_message(tmp_path):
    (tmp_path / "bad.ply").write_text("not a ply\n")
    with pytest.raises(sculpt.Error, match=r"bad\.ply: not a PLY file"):
        sculpt.load(str(tmp_path / "bad.ply"))
    (tmp_path / "cloud.ply").write_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                        "property float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n")
    with pytest.raises(sculpt.Error, match="point cloud is not a surface"):
        sculpt.load(str(tmp_path / "cloud.ply"))
    V, F = random_mesh(np.random.default_rng(1), 1)
    with pytest.raises(sculpt.Error, match=r"'\.fbx' is not a mesh format"):
        sculpt.Session(V, F).save(str(tmp_path / "out.fbx"))
    assert not (tmp_path / "out.fbx").exists()
