"""The PEP 517 build backend of `pip install .` (pyproject.toml names it, in-tree): builds the `sculpt` module
through the project's own CMake build and packs it, with the bundled assets, into a wheel.

No build requirement is fetched: the build uses what Debian's packages installed (.ci/install-deps), so pip is
run with --no-build-isolation (no package index is reached here):

    pip install --no-build-isolation .
    pip install --no-build-isolation --config-settings build-dir=build .   # reuse a build folder

The wheel holds sculpt.<abi>.so at the top of site-packages and the assets (default mesh, lattice library,
examples) as data under PREFIX/share/dmffd-sculpt/assets, where the module looks for them once installed
(src/app/cli_options.h: bundledAssetsFolder). The module links the system's shared libraries (assimp, GLFW,
OpenMP...), as the Debian package declares; the wheel is for this machine's Python and platform.
"""
import base64
import hashlib
import os
import shutil
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

NAME = "dmffd_sculpt"
VERSION = "0.1"
SOURCE = Path(__file__).resolve().parents[2]


def _metadata():
    return (f"Metadata-Version: 2.1\nName: dmffd-sculpt\nVersion: {VERSION}\n"
            "Summary: Direct-manipulation free-form deformation sculpting, free of self-intersection\n"
            "Requires-Python: >=3.7\nRequires-Dist: numpy\n")


def _tag():
    abi = f"cp{sys.version_info[0]}{sys.version_info[1]}"
    platform = sysconfig.get_platform().replace("-", "_").replace(".", "_")
    return f"{abi}-{abi}-{platform}"


def _wheel_text():
    return f"Wheel-Version: 1.0\nGenerator: dmffd-sculpt build_backend\nRoot-Is-Purelib: false\nTag: {_tag()}\n"


def _build_module(config_settings):
    """Configures (once) and builds the CMake target sculpt_python; returns the module's path."""
    settings = config_settings or {}
    build = Path(settings.get("build-dir", SOURCE / "build-pip"))
    if not build.is_absolute():
        build = SOURCE / build
    if not (build / "CMakeCache.txt").exists():
        subprocess.run(["cmake", "-S", str(SOURCE), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                        f"-DPython_EXECUTABLE={sys.executable}"], check=True, stdout=sys.stderr)
    jobs = str(os.cpu_count() or 2)
    subprocess.run(["cmake", "--build", str(build), "--target", "sculpt_python", "-j", jobs], check=True, stdout=sys.stderr)
    modules = sorted((build / "python").glob("sculpt*.so"))
    if not modules:
        raise RuntimeError(f"the build in {build} made no sculpt*.so in {build / 'python'}")
    return modules[0]


def _record_line(name, data):
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return f"{name},sha256={digest},{len(data)}"


def get_requires_for_build_wheel(config_settings=None):
    return []


def prepare_metadata_for_build_wheel(metadata_directory, config_settings=None):
    info = Path(metadata_directory) / f"{NAME}-{VERSION}.dist-info"
    info.mkdir(parents=True, exist_ok=True)
    (info / "METADATA").write_text(_metadata())
    (info / "WHEEL").write_text(_wheel_text())
    return info.name


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    module = _build_module(config_settings)
    wheel_name = f"{NAME}-{VERSION}-{_tag()}.whl"
    info = f"{NAME}-{VERSION}.dist-info"
    data = f"{NAME}-{VERSION}.data/data/share/dmffd-sculpt/assets"
    entries = [(module.name, module.read_bytes())]
    for path in sorted((SOURCE / "assets").rglob("*")):
        relative = path.relative_to(SOURCE / "assets")
        if path.is_file() and relative.parts[0] != "desktop":
            entries.append((f"{data}/{relative.as_posix()}", path.read_bytes()))
    entries.append((f"{info}/METADATA", _metadata().encode()))
    entries.append((f"{info}/WHEEL", _wheel_text().encode()))
    target = Path(wheel_directory) / wheel_name
    with zipfile.ZipFile(target, "w", zipfile.ZIP_DEFLATED) as wheel:
        record = []
        for name, content in entries:
            wheel.writestr(name, content)
            record.append(_record_line(name, content))
        record.append(f"{info}/RECORD,,")
        wheel.writestr(f"{info}/RECORD", "\n".join(record) + "\n")
    return wheel_name


def build_sdist(sdist_directory, config_settings=None):
    """The checkout as a source archive (git's tracked files)."""
    files = subprocess.run(["git", "-C", str(SOURCE), "ls-files"], check=True, capture_output=True, text=True).stdout.split()
    name = f"{NAME}-{VERSION}"
    archive = Path(sdist_directory) / f"{name}.tar.gz"
    staging = Path(sdist_directory) / name
    for relative in files:
        destination = staging / relative
        destination.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(SOURCE / relative, destination)
    (staging / "PKG-INFO").write_text(_metadata())
    shutil.make_archive(str(staging), "gztar", root_dir=sdist_directory, base_dir=name)
    shutil.rmtree(staging)
    return archive.name
