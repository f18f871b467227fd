"""Builds and installs the Python package `zeroreg` from this repository (docs/PYTHON.md).

    /usr/bin/python3 -m venv --system-site-packages ENV
    ENV/bin/pip install --no-build-isolation ./python

Offline, with Debian's setuptools, wheel and pybind11-dev (--no-build-isolation: pip would
otherwise fetch setuptools from an index). The extension is not compiled by setuptools: it is the
CMake target `zeroreg_python` of the project's build folder (ZEROREG_BUILD_DIR, default build/,
configured here when it is not yet), so it is the same library, built with the same flags, as the
CLI beside it, and a build from `bash scripts/setup.sh` is reused instead of compiled again.
The models fetched into assets/ go into the wheel as data files, ENV/share/zeroreg/assets, where
the module finds them (include/zeroreg/assets.hpp); without assets/ the wheel has no models.
"""

import hashlib
import os
import re
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
BUILD_DIR = os.path.join(REPO, os.environ.get("ZEROREG_BUILD_DIR", "build"))


def read(path):
    with open(path, encoding="utf-8") as f:
        return f.read()


def project_version():
    """The version of CMakeLists.txt's project(), the project's one version number."""
    match = re.search(r"project\(zeroreg\s+VERSION\s+([0-9.]+)", read(os.path.join(REPO, "CMakeLists.txt")))
    if not match:
        sys.exit("setup.py: no `project(zeroreg VERSION x.y.z` in CMakeLists.txt")
    return match.group(1)


def credits_section():
    """README's "Models and data (credits and licenses)" section, for the wheel's description."""
    readme = read(os.path.join(REPO, "README.md"))
    match = re.search(r"^## Models and data \(credits and licenses\)\n.*?(?=^## )", readme, re.S | re.M)
    if not match:
        sys.exit("setup.py: README.md has no '## Models and data (credits and licenses)' section")
    return match.group(0)


def model_data_files():
    """The verified files of assets/ as data_files under share/zeroreg/assets ([] if not fetched)."""
    assets = os.path.join(REPO, "assets")
    listing = os.path.join(REPO, "scripts", "assets.sha256")
    if not os.path.isdir(assets):
        print(f"setup.py: {assets} not found, the wheel has no models (bash scripts/fetch-assets.sh)")
        return []
    by_folder = {}
    for line in read(listing).splitlines():
        if not line.strip() or line.startswith("#"):
            continue
        expected, name = line.split(None, 1)
        path = os.path.join(assets, name.lstrip("*"))
        with open(path, "rb") as f:  # a missing file raises, naming it
            actual = hashlib.sha256(f.read()).hexdigest()
        if actual != expected:
            sys.exit(f"setup.py: {path}: sha256 mismatch; run bash scripts/fetch-assets.sh")
        folder = os.path.join("share", "zeroreg", "assets", os.path.dirname(name))
        by_folder.setdefault(folder, []).append(path)
    # The list itself lets the module verify the models without the source tree.
    by_folder.setdefault(os.path.join("share", "zeroreg", "assets"), []).append(listing)
    return sorted(by_folder.items())


def cache_value(name):
    """A variable of the build folder's CMakeCache.txt, or None."""
    cache = os.path.join(BUILD_DIR, "CMakeCache.txt")
    match = re.search(rf"^{name}:[A-Z]+=(.*)$", read(cache), re.M) if os.path.exists(cache) else None
    return match.group(1) if match else None


class CMakeBuild(build_ext):
    """Builds the extension with CMake and copies it where setuptools packs it."""

    def build_extension(self, ext):
        if cache_value("CMAKE_HOME_DIRECTORY") is None:
            python = os.path.realpath(getattr(sys, "_base_executable", sys.executable))
            subprocess.check_call(
                ["cmake", "-S", REPO, "-B", BUILD_DIR, "-DCMAKE_BUILD_TYPE=Release",
                 f"-DPython_EXECUTABLE={python}"]
            )
        if cache_value("ZEROREG_BUILD_PYTHON") in ("OFF", "0", "FALSE"):
            sys.exit(f"setup.py: {BUILD_DIR} is configured with ZEROREG_BUILD_PYTHON=OFF")
        jobs = os.environ.get("ZEROREG_JOBS", str(os.cpu_count() or 1))
        subprocess.check_call(["cmake", "--build", BUILD_DIR, "--target", "zeroreg_python", "-j", jobs])

        built = os.path.join(BUILD_DIR, "python", "zeroreg", "_zeroreg" + sysconfig.get_config_var("EXT_SUFFIX"))
        if not os.path.exists(built):
            sys.exit(
                f"setup.py: {built} was not built: {BUILD_DIR} builds the module for "
                f"{cache_value('Python_EXECUTABLE')}, not for {sys.executable}. Use that interpreter, "
                "or set ZEROREG_BUILD_DIR to another folder to configure a build for this one."
            )
        target = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        shutil.copy2(built, target)
        # What zeroreg takes from Open3D is in a module it loads when needed, looked for beside the
        # extension first (src/open3d_module/open3d_module.hpp); the target builds it there.
        module = os.path.join(os.path.dirname(built), "libzeroreg-open3d.so")
        if not os.path.exists(module):
            sys.exit(f"setup.py: {module} was not built (target zeroreg_open3d)")
        shutil.copy2(module, os.path.join(os.path.dirname(target), "libzeroreg-open3d.so"))
        # The module links ONNX Runtime (a shared library) when the build has it: the wheel carries
        # it beside the extension, which finds it through its $ORIGIN RPATH (CMakeLists.txt).
        ort = cache_value("ZEROREG_ORT_LIBRARY")
        if cache_value("ZEROREG_WITH_ONNXRUNTIME") != "OFF" and ort and os.path.exists(ort):
            shutil.copy2(os.path.realpath(ort), os.path.join(os.path.dirname(target), "libonnxruntime.so.1"))


os.makedirs(os.path.join(BUILD_DIR, "pip"), exist_ok=True)  # egg_base must exist
setup(
    name="zeroreg",
    version=project_version(),
    description="Registration of two RGB-D scans without 3D training (ZeroReg, CVPR 2025)",
    long_description=read(os.path.join(HERE, "zeroreg", "__init__.py")).split('"""')[1]
    + "\n"
    + credits_section(),
    long_description_content_type="text/markdown",
    # The project states no license of its own; the models shipped in share/zeroreg/assets keep
    # theirs (LICENSE files beside them, the description's credits section names them).
    license="models: XFeat, YOLOX-Nano, Detic CLIP embeddings Apache-2.0; Yolo-Fastest YOLO LICENSE v2",
    packages=["zeroreg"],
    ext_modules=[Extension("zeroreg._zeroreg", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    data_files=model_data_files(),
    install_requires=["numpy"],
    python_requires=">=3.9",
    zip_safe=False,
    # setuptools' scratch and egg-info go into the git-ignored build folder, not python/.
    options={"build": {"build_base": os.path.join(BUILD_DIR, "pip")},
             "egg_info": {"egg_base": os.path.join(BUILD_DIR, "pip")}},
)
