"""Camera files by format (mvtools.io.camera_files): the writer and reader of each format
chosen by name or by method, a hand-made camera back with its numbers, and a method that
names no format refused with the list of formats."""

from __future__ import annotations

import numpy as np
import pytest

from mvtools.geometry.camera import Camera
from mvtools.io.camera_files import read_camera_file, write_camera_file

#: A camera 0.1 to the right of the origin, looking along +z, with a principal point
#: off the centre: every number of K, R and t is checked after the round trip.
CAMERA = Camera(
    "cam1",
    np.array([[240.0, 0.0, 127.5], [0.0, 241.0, 95.5], [0.0, 0.0, 1.0]]),
    t=np.array([0.1, 0.0, 0.0]),
    size=(256, 192),
    depth_range=(2.0, 13.0),
)


@pytest.mark.parametrize(
    "name, method", [("cameras.txt", None), ("cameras.json", None), ("cameras.cfg", "json")]
)
def test_a_camera_comes_back_from_each_format(tmp_path, name, method):
    path = tmp_path / name
    write_camera_file(path, [CAMERA], method=method)
    back = read_camera_file(path, method=method)["cam1"]
    np.testing.assert_allclose(back.K, CAMERA.K, atol=1e-9)
    np.testing.assert_allclose(back.R, np.eye(3), atol=1e-9)
    np.testing.assert_allclose(back.t, CAMERA.t, atol=1e-12)
    if method == "json" or name.endswith(".json"):
        assert path.read_text().lstrip().startswith("{")
        assert back.size == (256, 192) and back.depth_range == (2.0, 13.0)
    else:
        assert not path.read_text().lstrip().startswith("{")


def test_a_method_that_names_no_format_is_refused(tmp_path):
    with pytest.raises(ValueError, match="'htm' is not a camera file format: mpeg or json"):
        write_camera_file(tmp_path / "cameras.txt", [CAMERA], method="htm")
    assert list(tmp_path.iterdir()) == []
