"""Pose traces (CSV of RVS/TMIV): both conventions, round trips, one-line errors.

The truth: the sample scene's MPEG-I JSON camera files, read field by field with the
json module and by read_json_cameras (the "omaf" rows are those fields); the MPEG
camera axes worked out by hand (yaw 90 looks along +x, pitch 90 along -y, roll 90 turns
the image x axis to +y) and rigs.rotation_about_y.
"""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from mvtools.errors import ConfigError, UsageError
from mvtools.geometry import Camera
from mvtools.io.json_cameras import read_json_cameras
from mvtools.io.pose_trace import (
    POSE_TRACE_CONVENTIONS,
    check_frames,
    read_pose_trace,
    write_pose_trace,
)
from mvtools.scene.rigs import axis_angle_rotation, rotation_about_y

SAMPLE = Path(__file__).resolve().parent.parent / "sample_data"
H = math.sqrt(0.5)

TEMPLATE = Camera(
    "virtual",
    [[240.0, 0.0, 127.5], [0.0, 240.0, 95.5], [0.0, 0.0, 1.0]],
    distortion=[0.01, -0.002],
    size=(256, 192),
    depth_range=(2.0, 13.0),
)


def _trace(tmp_path, text, name="trace.csv"):
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.mark.parametrize("rig", ["line", "arc"])
def test_omaf_rows_are_the_json_cameras(tmp_path, rig):
    path = SAMPLE / rig / "cameras.json"
    entries = json.loads(path.read_text())["cameras"]
    rows = ["X,Y,Z,Yaw,Pitch,Roll"]
    rows += [",".join(repr(float(v)) for v in e["Position"] + e["Rotation"]) for e in entries]
    trace = _trace(tmp_path, "\n".join(rows) + "\n")
    cameras = read_json_cameras(path)
    for entry, pose in zip(entries, read_pose_trace(trace, template=cameras[entries[0]["Name"]])):
        camera = cameras[entry["Name"]]
        assert np.array_equal(pose.R, camera.R)
        assert np.array_equal(pose.t, camera.t)
        assert np.array_equal(pose.K, camera.K)


def test_omaf_forward_is_x_left_is_y_up_is_z(tmp_path):
    # yaw 90, pitch -90 (OMAF x forward turned to the world's z): our identity
    trace = _trace(tmp_path, "0,0,0,90,-90,0\n1.5, -2, 3 , 0,0,0\n")
    first, second = read_pose_trace(trace, template=TEMPLATE)
    np.testing.assert_allclose(first.R, np.eye(3), atol=1e-15)
    # all angles zero: looking along world x, image right = world -y, image down = -z
    np.testing.assert_allclose(second.R, [[0, -1, 0], [0, 0, -1], [1, 0, 0]], atol=1e-15)
    np.testing.assert_array_equal(second.t, [1.5, -2.0, 3.0])


def test_mpeg_convention_hand_values(tmp_path):
    rows = ["0,0,0,90,0,0", "0,0,0,0,90,0", "0,0,0,0,0,90", "0,0,0,30,0,0", "0,0,0,90,45,0"]
    cameras = read_pose_trace(
        _trace(tmp_path, "\n".join(rows)), convention="mpeg", template=TEMPLATE
    )
    yaw90, pitch90, roll90, yaw30, yaw90_pitch45 = cameras
    np.testing.assert_allclose(yaw90.optical_axis, [1, 0, 0], atol=1e-15)
    np.testing.assert_allclose(pitch90.optical_axis, [0, -1, 0], atol=1e-15)
    np.testing.assert_allclose(roll90.R[0], [0, 1, 0], atol=1e-15)  # image x -> +y
    np.testing.assert_allclose(roll90.optical_axis, [0, 0, 1], atol=1e-15)
    np.testing.assert_allclose(yaw30.R, rotation_about_y(30.0), atol=1e-15)
    # pitch is applied in the turned frame: up by 45 degrees while looking along +x
    np.testing.assert_allclose(yaw90_pitch45.optical_axis, [H, -H, 0], atol=1e-15)
    np.testing.assert_allclose(yaw90_pitch45.R[0], [0, 0, -1], atol=1e-15)


def test_template_fields_and_names(tmp_path):
    cameras = read_pose_trace(_trace(tmp_path, "\n1,2,3,0,0,0\n\n4,5,6,0,0,0\n"), template=TEMPLATE)
    assert [c.name for c in cameras] == ["virtual_pose000", "virtual_pose001"]
    for camera in cameras:
        assert np.array_equal(camera.K, TEMPLATE.K)
        assert np.array_equal(camera.distortion, TEMPLATE.distortion)
        assert camera.size == (256, 192) and camera.depth_range == (2.0, 13.0)
    np.testing.assert_array_equal(cameras[1].t, [4, 5, 6])
    np.testing.assert_array_equal(TEMPLATE.t, [0, 0, 0])  # the template is left alone


@pytest.mark.parametrize("convention", POSE_TRACE_CONVENTIONS)
def test_round_trip(tmp_path, convention):
    rng = np.random.default_rng(5)
    cameras = [
        Camera(
            f"c{i}",
            TEMPLATE.K,
            R=axis_angle_rotation(rng.normal(size=3), rng.uniform(0, 180)),
            t=rng.normal(size=3),
        )
        for i in range(20)
    ]
    cameras.append(Camera("ones", TEMPLATE.K, R=np.eye(3), t=[0.1, 1 / 3, -2.5]))
    path = tmp_path / "out.csv"
    write_pose_trace(path, cameras, convention=convention)
    lines = path.read_text().splitlines()
    assert lines[0] == "X,Y,Z,Yaw,Pitch,Roll" and len(lines) == 22
    assert lines[-1].startswith("0.1,0.3333333333333333,-2.5,")
    back = read_pose_trace(path, convention=convention, template=TEMPLATE)
    for camera, pose in zip(cameras, back, strict=True):
        np.testing.assert_allclose(pose.R, camera.R, atol=1e-12, rtol=0)
        assert np.array_equal(pose.t, camera.t)


def test_mpeg_writes_hand_angles(tmp_path):
    path = tmp_path / "out.csv"
    write_pose_trace(path, [Camera("c", TEMPLATE.K, R=rotation_about_y(30.0))], convention="mpeg")
    yaw, pitch, roll = map(float, path.read_text().splitlines()[1].split(",")[3:])
    assert (yaw, pitch, roll) == pytest.approx((30.0, 0.0, 0.0), abs=1e-12)


def _error(path, *, kind=ConfigError, **options):
    with pytest.raises(kind) as caught:
        read_pose_trace(path, template=TEMPLATE, **options)
    error = caught.value
    assert error.exit_code == 2
    assert "\n" not in str(error)
    assert str(error).startswith(str(path))
    return error


def test_wrong_number_of_fields(tmp_path):
    path = _trace(tmp_path, "X,Y,Z,Yaw,Pitch,Roll\n" + "0,0,0,0,0,0\n" * 3 + "1,2,3,4\n")
    error = _error(path)
    assert error.line == 5
    assert str(error) == f"{path}:5: 4 fields, 6 needed (X,Y,Z,Yaw,Pitch,Roll)"


@pytest.mark.parametrize(
    ("row", "column", "shown"),
    [
        ("0,0,0,0,abc,0", "Pitch", "'abc' is not a number"),
        ("0,,0,0,0,0", "Y", "empty"),
        ("0,0,0,nan,0,0", "Yaw", "not a finite number"),
        ("0,0,inf,0,0,0", "Z", "not a finite number"),
        ("0,0,0,0,0,-Infinity", "Roll", "not a finite number"),
        ("1_0,0,0,0,0,0", "X", "is not a number"),
    ],
)
def test_bad_fields_name_file_line_and_column(tmp_path, row, column, shown):
    path = _trace(tmp_path, "0,0,0,0,0,0\n" + row + "\n")
    error = _error(path)
    assert (error.line, error.key) == (2, column)
    assert str(error).startswith(f"{path}:2: {column}: ")
    assert shown in str(error)


def test_a_header_that_is_not_ours_is_a_bad_field(tmp_path):
    error = _error(_trace(tmp_path, "x,y,z,heading,pitch,roll\n0,0,0,0,0,0\n"))
    assert (error.line, error.key) == (1, "X")
    assert "X,Y,Z,Yaw,Pitch,Roll" in str(error)


@pytest.mark.parametrize(
    "text", ["", "\n\n", "X,Y,Z,Yaw,Pitch,Roll\n", "x, y, z, yaw, pitch, roll\n"]
)
def test_no_rows(tmp_path, text):
    path = _trace(tmp_path, text)
    error = _error(path)
    assert "no poses" in str(error)


def test_fewer_rows_than_frames(tmp_path):
    path = _trace(tmp_path, "0,0,0,0,0,0\n1,0,0,0,0,0\n2,0,0,0,0,0\n")
    error = _error(path, frames=5)
    assert "3 poses" in str(error) and "5 frames" in str(error)
    assert [c.t[0] for c in read_pose_trace(path, template=TEMPLATE, frames=2)] == [0.0, 1.0]
    with pytest.raises(ConfigError, match=r"3 poses.*10 frames") as caught:
        check_frames(read_pose_trace(path, template=TEMPLATE), 10, path)
    assert str(caught.value).startswith(str(path)) and caught.value.exit_code == 2


def test_unknown_convention_and_missing_file(tmp_path):
    path = _trace(tmp_path, "0,0,0,0,0,0\n")
    with pytest.raises(UsageError) as caught:
        read_pose_trace(path, convention="opencv", template=TEMPLATE)
    assert caught.value.exit_code == 2 and caught.value.key == "convention"
    assert "'opencv'" in str(caught.value) and "omaf, mpeg" in str(caught.value)
    with pytest.raises(UsageError, match="omaf, mpeg") as caught:
        write_pose_trace(tmp_path / "out.csv", [TEMPLATE], convention="OMAF")
    assert caught.value.exit_code == 2
    assert not (tmp_path / "out.csv").exists()
    missing = _error(tmp_path / "missing.csv", kind=UsageError)
    assert "no such pose trace" in str(missing)


def test_write_refuses_what_has_no_pose(tmp_path):
    with pytest.raises(UsageError, match="no cameras"):
        write_pose_trace(tmp_path / "out.csv", [])
    reflected = Camera("mirror", TEMPLATE.K, R=np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(UsageError, match="mirror"):
        write_pose_trace(tmp_path / "out.csv", [reflected])
    assert not (tmp_path / "out.csv").exists()
