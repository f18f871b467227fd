"""The Open3D module (docs/INSTALL.md "The Open3D module"): the package finds its own copy."""
import os

import zeroreg


def test_the_package_loads_the_open3d_module_beside_its_extension():
    path = zeroreg.open3d_module_path()
    assert os.path.basename(path) == "libzeroreg-open3d.so"
    assert os.path.isfile(path)
    # Beside the compiled extension, wherever the package is (build tree, venv, wheel).
    assert os.path.dirname(os.path.realpath(path)) == os.path.dirname(
        os.path.realpath(zeroreg._zeroreg.__file__)
    )
