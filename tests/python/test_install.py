"""Installed as a user installs it: `pip install .` into a venv, and `cmake --install` into a prefix. Each runs
from a folder outside the tree, with nothing of the build on the path, and finds its bundled assets."""
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import SOURCE_DIR

BUILD_DIR = Path(os.environ.get("SCULPT_BUILD_DIR", SOURCE_DIR / "build"))

# A short check of an installed module: it is the installed file, its default mesh is the installed copy, and a
# drag on it applies.
CHECK_MODULE = """
import sys, sculpt
prefix = sys.argv[1]
assert sculpt.__file__.startswith(prefix), sculpt.__file__
mesh = sculpt.default_mesh_path()
assert mesh.startswith(prefix), mesh
s = sculpt.load(mesh, lattice={"resolution": [5, 5, 5]})
v = s.positions[0].copy()
r = s.drag_vertex(0, [v[0] + 0.01, v[1], v[2]])
assert r["status"] == "applied", r
print("ok", sculpt.__file__)
"""


def clean_environment():
    """The environment without the build's module on PYTHONPATH."""
    env = dict(os.environ)
    env.pop("PYTHONPATH", None)
    return env


def test_pip_install_into_a_venv_imports_from_outside_the_tree(tmp_path):
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(venv)], check=True)
    python = venv / "bin" / "python"
    # The build folder ctest built is reused (the wheel's module is its sculpt_python target).
    pip = subprocess.run([str(python), "-m", "pip", "install", "--no-build-isolation", "--no-index", "--quiet",
                          "--config-settings", f"build-dir={BUILD_DIR}", str(SOURCE_DIR)],
                         cwd=tmp_path, env=clean_environment(), capture_output=True, text=True)
    assert pip.returncode == 0, pip.stdout + pip.stderr
    outside = tmp_path / "elsewhere"
    outside.mkdir()
    run = subprocess.run([str(python), "-c", CHECK_MODULE, str(venv)], cwd=outside, env=clean_environment(),
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stdout + run.stderr
    assert (venv / "share" / "dmffd-sculpt" / "assets" / "lattices").is_dir()


def test_cmake_install_runs_headless_from_any_folder_and_the_module_imports(tmp_path):
    prefix = tmp_path / "prefix"
    install = subprocess.run(["cmake", "--install", str(BUILD_DIR), "--prefix", str(prefix)], capture_output=True, text=True)
    assert install.returncode == 0, install.stdout + install.stderr
    program = prefix / "bin" / "sculpt"
    assert program.is_file()
    outside = tmp_path / "elsewhere"
    outside.mkdir()
    # Headless on the bundled default mesh (no --input), the installed demo script.
    script = prefix / "share" / "dmffd-sculpt" / "assets" / "demo.json"
    run = subprocess.run([str(program), "--headless", "--script", str(script), "--output", "out.obj"], cwd=outside,
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stdout + run.stderr
    assert f"loaded {prefix}/share/dmffd-sculpt/assets/default.obj" in run.stdout, run.stdout
    assert (outside / "out.obj").stat().st_size > 0
    env = clean_environment()
    env["PYTHONPATH"] = str(prefix / "lib" / "python3" / "dist-packages")
    module = subprocess.run([sys.executable, "-c", CHECK_MODULE, str(prefix)], cwd=outside, env=env, capture_output=True, text=True)
    assert module.returncode == 0, module.stdout + module.stderr
    # The desktop entry passes the freedesktop check, and its icon is where desktops look.
    entry = prefix / "share" / "applications" / "dmffd-sculpt.desktop"
    validator = shutil.which("desktop-file-validate")
    assert validator, "desktop-file-validate is missing (.ci/install-deps installs desktop-file-utils)"
    check = subprocess.run([validator, str(entry)], capture_output=True, text=True)
    assert check.returncode == 0 and not check.stdout.strip(), check.stdout + check.stderr
    assert "Exec=sculpt %f" in entry.read_text()
    assert (prefix / "share" / "icons" / "hicolor" / "scalable" / "apps" / "dmffd-sculpt.svg").is_file()
