"""The one version number (CMakeLists.txt's project version) as Python sees it."""

import importlib.metadata
import os
import re

import zeroreg
from conftest import REPO


def cmake_project_version():
    with open(os.path.join(REPO, "CMakeLists.txt"), encoding="utf-8") as f:
        return re.search(r"project\(zeroreg\s+VERSION\s+([0-9.]+)", f.read()).group(1)


def test_version_is_the_cmake_project_version():
    assert zeroreg.__version__ == cmake_project_version()


def test_installed_metadata_has_the_same_version():
    # Only an installed package has metadata; the build tree's module (ZEROREG_PYTHONPATH) has none.
    try:
        installed = importlib.metadata.version("zeroreg")
    except importlib.metadata.PackageNotFoundError:
        assert os.environ.get("ZEROREG_PYTHONPATH"), "zeroreg imported but not installed"
        return
    assert installed == zeroreg.__version__
    # The wheel credits the models it ships (their LICENSE files are installed beside them).
    metadata = importlib.metadata.metadata("zeroreg")
    assert "Apache-2.0" in metadata["License"]
    assert "## Models and data (credits and licenses)" in metadata.get_payload()


def test_result_json_names_the_version(result_20_0_from_paths):
    assert result_20_0_from_paths.to_dict()["zeroreg_version"] == zeroreg.__version__
