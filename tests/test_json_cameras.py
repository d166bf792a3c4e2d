"""MPEG-I sequence files as RVS 4.0 and TMIV read them: keys, pixel centres, depth ranges.

The truth here is the MPEG-I camera model written out in the tests (OMAF axes,
``Rz(yaw) Ry(pitch) Rx(roll)``, pixel centres at integer + 0.5), the pinhole model of the
VSRS text files (pixel centres at integers), and the RVS file written by hand for the
Cones camera file.
"""

import json
import logging
from fractions import Fraction

import numpy as np
import pytest
from program_runner import assert_one_line_error, invoke
from shared_data import shared_data

from mvtools.cli import convert
from mvtools.errors import UsageError
from mvtools.geometry import Camera
from mvtools.io.cameras import read_cameras, write_cameras
from mvtools.io.json_cameras import read_json_sequence, write_json_cameras

CONES = ("reference_outputs", "cones_mvd")

RVS_CAMERA_KEYS = {
    "Name",
    "Position",
    "Rotation",
    "Depthmap",
    "Background",
    "Depth_range",
    "Resolution",
    "Projection",
    "Focal",
    "Principle_point",
    "BitDepthColor",
    "BitDepthDepth",
    "ColorSpace",
    "DepthColorSpace",
    "HasInvalidDepth",
}


def _rotation_about(axis, degrees):
    """The right-handed rotation by ``degrees`` about coordinate axis 0, 1 or 2."""
    c, s = np.cos(np.radians(degrees)), np.sin(np.radians(degrees))
    i, j = (axis + 1) % 3, (axis + 2) % 3
    rotation = np.eye(3)
    rotation[i, i], rotation[i, j], rotation[j, i], rotation[j, j] = c, -s, s, c
    return rotation


def _euler(yaw, pitch, roll):
    """Rz(yaw) Ry(pitch) Rx(roll): camera to world in MPEG-I files."""
    return _rotation_about(2, yaw) @ _rotation_about(1, pitch) @ _rotation_about(0, roll)


def _json_pixel(entry, point):
    """MPEG-I projection: camera point p = R^T (X - Position) in OMAF axes (x forward,
    y left, z up); pixel (cx - fx p_y / p_x, cy - fy p_z / p_x) with pixel centres at
    integer + 0.5. Returns (u, v, depth)."""
    p = _euler(*entry["Rotation"]).T @ (np.asarray(point) - entry["Position"])
    (fx, fy), (cx, cy) = entry["Focal"], entry["Principle_point"]
    return np.array([cx - fx * p[1] / p[0], cy - fy * p[2] / p[0], p[0]])


def _text_pixel(camera, point):
    """VSRS text model: x = R (X - t), pixel (fx x/z + cx, fy y/z + cy), centres at integers."""
    x = camera.R @ (np.asarray(point) - camera.t)
    return np.array(
        [camera.fx * x[0] / x[2] + camera.cx, camera.fy * x[1] / x[2] + camera.cy, x[2]]
    )


def _entries(path):
    return {entry["Name"]: entry for entry in json.loads(path.read_text())["cameras"]}


def _rig():
    """Two rotated cameras with different, off-centre principal points."""
    first = Camera(
        "left",
        [[1200.0, 0, 700.25], [0, 1180.0, 390.75], [0, 0, 1]],
        R=_rotation_about(1, 12.0) @ _rotation_about(0, -7.0),
        t=[-0.3, 0.1, 0.05],
        size=(1280, 720),
    )
    second = Camera(
        "right",
        [[1200.0, 0, 611.0], [0, 1180.0, 344.5], [0, 0, 1]],
        R=_rotation_about(2, 20.0) @ _rotation_about(1, -15.0),
        t=[0.4, -0.05, 0.2],
        size=(1280, 720),
    )
    return [first, second]


def test_json_pixel_centres_are_half_a_pixel_past_the_text_files(tmp_path):
    cameras = _rig()
    write_cameras(tmp_path / "rig.txt", cameras)
    code, _, stderr = invoke(
        convert.command,
        tmp_path / "rig.txt",
        "-o",
        tmp_path / "rig.json",
        "--depth-range",
        0.5,
        40,
    )
    assert code == 0, stderr
    entries = _entries(tmp_path / "rig.json")
    assert entries["left"]["Principle_point"] == [700.75, 391.25]
    assert entries["right"]["Principle_point"] == [611.5, 345.0]
    points = [[0.2, -0.4, 6.0], [-1.5, 0.9, 11.0], [0.7, 0.3, 3.5]]
    for camera in cameras:
        for point in points:
            text = _text_pixel(camera, point)
            assert text[2] > 0
            # The same ray: JSON pixel (u + 0.5, v + 0.5) is the text file's (u, v).
            np.testing.assert_allclose(
                _json_pixel(entries[camera.name], point), text + [0.5, 0.5, 0], rtol=0, atol=1e-9
            )
    code, _, stderr = invoke(convert.command, tmp_path / "rig.json", "-o", tmp_path / "back.txt")
    assert code == 0, stderr
    for camera in cameras:
        back = read_cameras(tmp_path / "back.txt")[camera.name]
        np.testing.assert_array_equal(back.K, camera.K)
        np.testing.assert_array_equal(back.t, camera.t)
        np.testing.assert_allclose(back.R, camera.R, rtol=0, atol=1e-15)


def test_cones_converts_to_the_hand_written_rvs_file(tmp_path):
    text = shared_data(*CONES, "cam_param_cones.txt")
    reference = json.loads(shared_data(*CONES, "rvs_cones_cameras.json").read_text())
    code, _, stderr = invoke(
        convert.command,
        text,
        "-o",
        tmp_path / "cones.json",
        "--size",
        "448x368",
        "--depth-range",
        72.727273,
        888.888889,
        "--fps",
        1,
    )
    assert code == 0, stderr
    written = json.loads((tmp_path / "cones.json").read_text())
    assert written["Fps"] == reference["Fps"] and written["Frames_number"] == 1
    assert float(written["Version"]) >= float(reference["Version"])
    # VSRS's principal point (223.5, 183.5) was written (224, 184) by hand for RVS.
    for ours, theirs in zip(written["cameras"], reference["cameras"]):
        assert set(ours) == set(theirs)
        for key in (
            "Principle_point",
            "Focal",
            "Resolution",
            "Depth_range",
            "Depthmap",
            "Background",
            "BitDepthColor",
            "BitDepthDepth",
            "HasInvalidDepth",
        ):
            assert ours[key] == theirs[key], key
    # The hand-written file turns the world into OMAF axes (X_omaf = M^T X, M our axes in
    # OMAF's); ours keeps the text file's world. Every point lands on the same pixel.
    to_omaf = np.array([[0.0, 0, 1], [-1, 0, 0], [0, -1, 0]])
    rng = np.random.default_rng(3)
    points = np.column_stack(
        [rng.uniform(-5, 5, 20), rng.uniform(-4, 4, 20), rng.uniform(80, 800, 20)]
    )
    for ours, theirs in zip(written["cameras"], reference["cameras"]):
        for point in points:
            np.testing.assert_allclose(
                _json_pixel(ours, point), _json_pixel(theirs, to_omaf @ point), rtol=0, atol=1e-9
            )


def test_a_complete_sequence_file(tmp_path):
    write_json_cameras(
        tmp_path / "rig.json", _rig(), depth_range=(0.5, 40.0), fps=25, frame_count=300
    )
    document = json.loads((tmp_path / "rig.json").read_text())
    assert list(document) == ["Version", "Content_name", "Fps", "Frames_number", "cameras"]
    assert document["Version"] == "4.0" and document["Content_name"] == "rig"
    assert document["Fps"] == 25 and document["Frames_number"] == 300
    for entry in document["cameras"]:
        assert set(entry) == RVS_CAMERA_KEYS
        assert entry["Depthmap"] == 1 and entry["Background"] == 0
        assert entry["HasInvalidDepth"] is False
        assert entry["Projection"] == "Perspective" and entry["Depth_range"] == [0.5, 40.0]


def test_json_to_json_keeps_video_and_sequence_fields(tmp_path):
    entry = {
        "Name": "v0",
        "Position": [0, 0, 0],
        "Rotation": [10, 0, 0],
        "Depthmap": 1,
        "Background": 1,
        "Depth_range": [0.3, 60],
        "Resolution": [2048, 1088],
        "Projection": "Perspective",
        "Focal": [1346.1, 1346.1],
        "Principle_point": [1024, 544],
        "BitDepthColor": 10,
        "BitDepthDepth": 16,
        "ColorSpace": "YUV420",
        "DepthColorSpace": "YUV400",
        "HasInvalidDepth": True,
    }
    source = tmp_path / "in.json"
    source.write_text(
        json.dumps(
            {
                "Version": "4.0",
                "Content_name": "Painter",
                "Fps": 30,
                "Frames_number": 300,
                "cameras": [entry],
            }
        )
    )
    code, _, stderr = invoke(convert.command, source, "-o", tmp_path / "out.json")
    assert code == 0, stderr
    written = json.loads((tmp_path / "out.json").read_text())
    assert (written["Content_name"], written["Fps"], written["Frames_number"]) == (
        "Painter",
        30,
        300,
    )
    camera = written["cameras"][0]
    np.testing.assert_allclose(camera.pop("Rotation"), entry["Rotation"], rtol=0, atol=1e-12)
    assert camera == {key: value for key, value in entry.items() if key != "Rotation"}
    sequence = read_json_sequence(tmp_path / "out.json")
    assert sequence.videos["v0"].bit_depth_depth == 16
    assert (sequence.cameras["v0"].cx, sequence.cameras["v0"].cy) == (1023.5, 543.5)


def test_principal_point_is_exact_where_adding_half_a_pixel_rounds(tmp_path):
    cx = 511.5 + 2.0**-44  # one unit in the last place above 511.5
    # cx + 0.5 reaches 512, where floats are twice as coarse: float arithmetic loses cx.
    assert (cx + 0.5) - 0.5 != cx
    camera = Camera("c", [[900.0, 0, cx], [0, 900.0, 255.75], [0, 0, 1]], size=(1024, 512))
    write_json_cameras(tmp_path / "c.json", [camera], depth_range=(1.0, 10.0))
    written = (tmp_path / "c.json").read_text()
    number = written.split('"Principle_point": [')[1].split(",")[0]
    assert Fraction(number) == Fraction(cx) + Fraction(1, 2)
    write_cameras(tmp_path / "c.txt", read_json_sequence(tmp_path / "c.json").cameras)
    back = read_cameras(tmp_path / "c.txt")["c"]
    assert back.cx == cx and back.cy == 255.75


def test_negative_vsrs_depth_range_is_written_in_front_of_the_cameras(tmp_path):
    camera = Camera(
        "n",
        [[1000.0, 0, 320.0], [0, 1000.0, 240.0], [0, 0, 1]],
        R=_rotation_about(1, 30.0),
        t=[1.0, 2.0, 3.0],
        size=(640, 480),
    )
    write_cameras(tmp_path / "n.txt", [camera])
    code, _, stderr = invoke(
        convert.command, tmp_path / "n.txt", "-o", tmp_path / "n.json", "--depth-range", -2, -50
    )
    assert code == 0, stderr
    assert "reflected through its origin" in stderr
    entry = _entries(tmp_path / "n.json")["n"]
    assert entry["Depth_range"] == [2.0, 50.0]
    assert entry["Position"] == [-1.0, -2.0, -3.0]
    # A point the VSRS camera sees at z = -10: the JSON camera sees its reflection -X at
    # depth +10 on the same pixel.
    point = camera.t + camera.R.T @ np.array([0.3, -0.2, -10.0])
    text = _text_pixel(camera, point)
    assert text[2] == pytest.approx(-10.0)
    np.testing.assert_allclose(
        _json_pixel(entry, -point), [text[0] + 0.5, text[1] + 0.5, 10.0], rtol=0, atol=1e-9
    )


@pytest.mark.parametrize(
    "znear, zfar, fragment",
    [
        (-2, 50, "depth range (near -2, far 50) needs 0 < near < far, or far < near < 0"),
        (50, 2, "depth range (near 50, far 2)"),
        (1, "inf", "depth range (near 1, far inf)"),
    ],
)
def test_depth_ranges_that_face_no_way_are_refused(tmp_path, znear, zfar, fragment):
    write_cameras(tmp_path / "rig.txt", _rig())
    code, _, stderr = invoke(
        convert.command,
        tmp_path / "rig.txt",
        "-o",
        tmp_path / "rig.json",
        "--depth-range",
        znear,
        zfar,
    )
    assert code == 2
    assert_one_line_error(stderr, "rig.json", "camera 'left'", fragment)
    assert not (tmp_path / "rig.json").exists()


def test_positive_and_negative_ranges_in_one_file_are_refused(tmp_path):
    front, behind = _rig()
    front.depth_range, behind.depth_range = (1.0, 10.0), (-1.0, -10.0)
    with pytest.raises(
        UsageError,
        match="camera 'left' has a positive depth range and camera 'right' a negative one",
    ):
        write_json_cameras(tmp_path / "mixed.json", [front, behind])


def test_far_depth_above_1000_and_missing_fields_are_warned(tmp_path, caplog):
    with caplog.at_level(logging.WARNING, logger="mvtools"):
        write_json_cameras(tmp_path / "far.json", _rig(), depth_range=(1.0, 2000.0))
        write_json_cameras(tmp_path / "bare.json", [Camera("b", np.diag([500.0, 500.0, 1.0]))])
    assert "far depth above 1000 for camera left, right, which RVS refuses" in caplog.text
    assert "no Depth_range for camera b" in caplog.text
    assert "no Resolution for camera b" in caplog.text


@pytest.mark.parametrize(
    "field, value, fragment",
    [
        ("Depthmap", 2, "Depthmap must be 0, 1, true or false, got 2"),
        ("BitDepthDepth", 10.5, "BitDepthDepth must be an integer >= 1, got 10.5"),
        ("Depth_range", [5, 1], "Depth_range must be [near, far] with 0 < near < far"),
        ("ColorSpace", 420, "ColorSpace must be a non-empty string, got 420"),
    ],
)
def test_malformed_fields_are_one_line_errors(tmp_path, field, value, fragment):
    entry = {
        "Name": "v0",
        "Position": [0, 0, 0],
        "Rotation": [0, 0, 0],
        "Projection": "Perspective",
        "Focal": [1000, 1000],
        "Principle_point": [320, 240],
        field: value,
    }
    (tmp_path / "bad.json").write_text(json.dumps({"cameras": [entry]}))
    code, _, stderr = invoke(convert.command, tmp_path / "bad.json", "-o", tmp_path / "out.txt")
    assert code == 2
    assert_one_line_error(stderr, "bad.json", "v0", fragment)
