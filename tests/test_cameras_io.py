"""Camera parameter files: MPEG text (VSRS/DERS), 3D-HTM 1D files, MPEG-I JSON."""

import json
import logging

import numpy as np
import pytest
from shared_data import data_root, shared_data

from mvtools.errors import ConfigError, UsageError
from mvtools.geometry import Camera, backproject, project
from mvtools.io.cameras import get_camera, read_cameras, read_htm_cameras, write_cameras
from mvtools.io.json_cameras import VideoDescription, read_json_cameras, write_json_cameras

CAMERA_FOLDER = ("mpeg", "vsrs_camera_parameters")
KENDO_CAMERAS = ("mpeg", "kendo", "config", "VSRS", "cam_param_kendo.cfg")


def _shipped_camera_files():
    folder = data_root().joinpath(*CAMERA_FOLDER)
    if not folder.is_dir():
        # One case that skips (or fails under MVTOOLS_REQUIRE_DATA) through shared_data.
        return [CAMERA_FOLDER]
    return [CAMERA_FOLDER + (path.name,) for path in sorted(folder.iterdir())] + [KENDO_CAMERAS]


SHIPPED = pytest.mark.parametrize("parts", _shipped_camera_files(), ids=lambda parts: parts[-1])


def _camera_file(parts):
    path = shared_data(*parts)
    if path.is_dir():
        pytest.fail(f"no camera files found in {path}")
    return path


def _numbers(camera):
    return camera.K, camera.R, camera.t, camera.distortion


def test_all_shipped_camera_files_are_tested():
    folder = shared_data(*CAMERA_FOLDER)
    assert len(list(folder.iterdir())) == 23


@SHIPPED
def test_every_shipped_file_loads_without_warnings(parts, caplog):
    with caplog.at_level(logging.WARNING, logger="mvtools"):
        cameras = read_cameras(_camera_file(parts))
    assert caplog.records == []
    assert len(cameras) >= 2
    for name, camera in cameras.items():
        assert camera.name == name
        assert name.startswith(("param_", "inter_"))
        np.testing.assert_array_equal(camera.K[2], [0, 0, 1])
        assert camera.fx > 0 and camera.fy > 0
        np.testing.assert_allclose(camera.R @ camera.R.T, np.eye(3), atol=1e-5)
        np.testing.assert_array_equal(camera.distortion, [0, 0])
        assert camera.size is None and camera.depth_range is None


@SHIPPED
def test_write_read_round_trip_is_exact(parts, tmp_path):
    cameras = read_cameras(_camera_file(parts))
    for transposed in (False, True):
        out = tmp_path / f"cameras_{transposed}.txt"
        write_cameras(out, cameras, transposed_rotation=transposed)
        again = read_cameras(out, transposed_rotation=transposed)
        assert list(again) == list(cameras)
        for name, camera in cameras.items():
            for original, reread in zip(_numbers(camera), _numbers(again[name])):
                assert np.array_equal(original, reread)


def test_spot_values_of_shipped_files():
    kendo = read_cameras(shared_data(*KENDO_CAMERAS))
    np.testing.assert_array_equal(kendo["param_kendo01"].t, [5.0, 0.0, 0.0])
    np.testing.assert_array_equal(kendo["param_kendo03"].t, [15.0, 0.0, 0.0])
    np.testing.assert_array_equal(
        kendo["param_kendo01"].K, [[2241.25607, 0, 701.5], [0, 2241.25607, 514.5], [0, 0, 1]]
    )
    assert kendo["param_kendo02.5"].t[0] == 12.5
    assert len(kendo) == 36

    news = read_cameras(shared_data(*CAMERA_FOLDER, "cam_param_news.txt"))
    np.testing.assert_array_equal(news["param_news00"].R, np.diag([1.0, -1.0, -1.0]))
    assert news["param_news01"].t[0] == 155.2750267587332

    champagne = read_cameras(shared_data(*CAMERA_FOLDER, "cam_param_champagne.txt"))
    assert champagne["param_champ00"].cx == -832.1011
    assert len(champagne) == 80

    poznan = read_cameras(shared_data(*CAMERA_FOLDER, "cam_param_poznan_street.txt"))
    assert {"param_cam4.5", "param_cam3.5a"} <= set(poznan)


def test_butterfly_arc_file_loads_its_cameras_despite_the_header_table():
    cameras = read_cameras(
        shared_data(*CAMERA_FOLDER, "cam_param_bbb_butterfly2_arc+Znear-far.txt")
    )
    assert list(cameras) == [f"param_ptm{index:02d}" for index in range(5, 85)]
    first = cameras["param_ptm05"]
    assert first.R[0, 0] == 0.939692620786 and first.R[0, 2] == -0.342020143326
    np.testing.assert_array_equal(first.t, [-0.530131222155, 0.0, -1.45652356222])


def test_transposed_rotation_option(tmp_path):
    path = shared_data(*CAMERA_FOLDER, "cam_param_lovebird1_original.txt")
    plain = read_cameras(path)["param_loveb1_001"]
    transposed = read_cameras(path, transposed_rotation=True)["param_loveb1_001"]
    np.testing.assert_array_equal(transposed.R, plain.R.T)
    np.testing.assert_array_equal(transposed.t, plain.t)
    write_cameras(tmp_path / "t.txt", [plain], transposed_rotation=True)
    rows = (tmp_path / "t.txt").read_text().splitlines()
    # The first [R|t] row of a transposed file holds the first column of R.
    assert [float(x) for x in rows[6].split()] == [*plain.R[:, 0], plain.t[0]]


def _write(tmp_path, text, name="cam.txt"):
    path = tmp_path / name
    path.write_bytes(text.encode())
    return path


def _block(name, tx=0.0, separator="\n"):
    rows = [
        "1000.0 0.0 320.0",
        "0.0 1000.0 240.0",
        "0.0 0.0 1.0",
        "0.0",
        "0.0",
        f"1.0 0.0 0.0 {tx}",
        "0.0 1.0 0.0 0.0",
        "0.0 0.0 1.0 0.0",
    ]
    return name + separator + separator.join(rows) + separator


def test_layout_variants_of_the_field(tmp_path, caplog):
    text = (
        "#ViewNum ZNear ZFar\r\n1 0.5 -2.0\r\n2 0.6 -2.1\r\n\r\n"
        + _block("camA \t", 1.5, separator=" \t\r\n")
        + "Some header words\r\n"
        # Line breaks inside a block do not matter: all 23 numbers on the name's line.
        + "camB "
        + _block("", -2.0, separator=" ").strip()
        + "   \r\n"
        + "# a comment with numbers 1 2 3\r\n"
    )
    with caplog.at_level(logging.WARNING, logger="mvtools"):
        cameras = read_cameras(_write(tmp_path, text))
    assert caplog.records == []
    assert list(cameras) == ["camA", "camB"]
    assert cameras["camA"].t[0] == 1.5 and cameras["camB"].t[0] == -2.0
    assert cameras["camB"].cy == 240.0


def test_short_block_names_file_line_and_camera(tmp_path):
    short = _block("param_cam2", 3.0).replace("0.0 0.0 1.0 0.0\n", "0.0 0.0 1.0\n")
    path = _write(tmp_path, _block("param_cam1") + "\n" + short + "\n" + _block("param_cam3"))
    with pytest.raises(ConfigError) as caught:
        read_cameras(path)
    err = caught.value
    assert (err.path, err.line, err.key) == (str(path), 11, "param_cam2")
    assert str(err) == f"{path}:11: param_cam2: camera block has 22 numbers, 23 needed"


def test_short_block_at_the_end_of_the_file(tmp_path):
    path = _write(tmp_path, _block("param_cam1") + "\nparam_cam2\n1.0 2.0\n")
    with pytest.raises(ConfigError, match="camera block has 2 numbers, 23 needed") as caught:
        read_cameras(path)
    assert caught.value.line == 11


def test_extra_numbers_after_a_block_are_warned(tmp_path, caplog):
    path = _write(tmp_path, _block("camA", 1.0) + "7.0 8.0\n" + _block("camB"))
    with caplog.at_level(logging.WARNING, logger="mvtools"):
        cameras = read_cameras(path)
    assert cameras["camA"].t[0] == 1.0
    assert "camA: camera block has 25 numbers" in caplog.text


def test_file_without_cameras_is_an_error(tmp_path):
    with pytest.raises(ConfigError, match="no camera found"):
        read_cameras(_write(tmp_path, "# nothing\n1 2 3\n"))


def test_missing_file_is_a_usage_error(tmp_path):
    with pytest.raises(UsageError, match="no such camera parameter file"):
        read_cameras(tmp_path / "absent.txt")


def test_duplicate_name_is_warned_and_the_last_kept(tmp_path, caplog):
    path = _write(
        tmp_path, _block("camA", 1.0) + "\n" + _block("camB") + "\n" + _block("camA", 2.0)
    )
    with caplog.at_level(logging.WARNING, logger="mvtools"):
        cameras = read_cameras(path)
    assert cameras["camA"].t[0] == 2.0
    assert len(cameras) == 2
    [record] = caplog.records
    assert f"{path}:21" in record.getMessage() and "'camA'" in record.getMessage()
    assert "first at line 1" in record.getMessage()


def test_non_orthonormal_rotation_is_warned(tmp_path, caplog):
    path = _write(
        tmp_path, _block("camA") + _block("camB").replace("0.0 1.0 0.0 0.0", "0.0 1.1 0.0 0.0")
    )
    with caplog.at_level(logging.WARNING, logger="mvtools"):
        cameras = read_cameras(path)
    assert cameras["camB"].R[1, 1] == 1.1
    [record] = caplog.records
    assert "camB" in record.getMessage() and "not orthonormal" in record.getMessage()


def test_unknown_camera_name_suggests_the_closest(tmp_path):
    cameras = read_cameras(_write(tmp_path, _block("param_kendo01") + _block("param_kendo03")))
    assert get_camera(cameras, "param_kendo03") is cameras["param_kendo03"]
    with pytest.raises(ConfigError) as caught:
        get_camera(cameras, "param_kendo1", path="cam.txt", key="LeftCameraName")
    assert str(caught.value).startswith("cam.txt: LeftCameraName: no camera 'param_kendo1'")
    assert "did you mean 'param_kendo01'" in str(caught.value)
    with pytest.raises(ConfigError, match="the file has 'param_kendo01', 'param_kendo03'"):
        get_camera(cameras, "left")


def test_write_refuses_what_cannot_be_read_back(tmp_path):
    good = Camera("camA", np.diag([1000.0, 1000.0, 1.0]))
    out = tmp_path / "out.txt"
    for bad in (
        Camera("two words", good.K),
        Camera("12.5", good.K),
        Camera("camB", good.K, distortion=[0.1, 0.0, 0.01, 0.0]),
    ):
        with pytest.raises(UsageError):
            write_cameras(out, [good, bad])
    with pytest.raises(UsageError, match="given twice"):
        write_cameras(out, [good, good])
    assert not out.exists()
    assert list(tmp_path.iterdir()) == []


def test_written_layout(tmp_path):
    camera = Camera(
        "camA", [[1000.5, 0, 320], [0, 1001, 240], [0, 0, 1]], t=[5, 0, 0], distortion=[0.25]
    )
    write_cameras(tmp_path / "c.txt", [camera])
    assert (tmp_path / "c.txt").read_text() == (
        "camA\n1000.5 0.0 320.0\n0.0 1001.0 240.0\n0.0 0.0 1.0\n0.25\n0.0\n"
        "1.0 0.0 0.0 5.0\n0.0 1.0 0.0 0.0\n0.0 0.0 1.0 0.0\n\n"
    )


# ---------------------------------------------------------------- 3D-HTM 1D files


def test_htm_kendo_cameras_match_the_vsrs_file():
    htm = read_htm_cameras(shared_data("mpeg", "kendo", "config", "HTM", "cam_kendo.cfg"))
    vsrs = read_cameras(shared_data(*KENDO_CAMERAS))
    assert list(htm) == ["1", "3", "5"]
    for view in htm:
        camera, reference = htm[view], vsrs[f"param_kendo0{view}"]
        assert camera.fx == camera.fy == reference.fx
        assert camera.cx == reference.cx and camera.cy == 0.0
        np.testing.assert_array_equal(camera.t, reference.t)
        np.testing.assert_array_equal(camera.R, np.eye(3))
        assert camera.depth_range == (448.251214, 11206.28035)


def test_htm_rows_are_chosen_by_frame(tmp_path):
    path = _write(
        tmp_path,
        "#ViewNum StartFrame EndFrame FocalLength Position CShift ZNear ZFar\n"
        "0 0 9 1000 1.0 320 10 100\n0 10 19 1000 2.0 320 10 100\n"
        "1 0 19 1000 3.0 330\n",
    )
    early, late = read_htm_cameras(path), read_htm_cameras(path, frame=12)
    assert early["0"].t[0] == 1.0 and late["0"].t[0] == 2.0
    assert early["1"].depth_range is None and early["1"].cx == 330.0
    with pytest.raises(ConfigError, match="no camera row covers frame 20"):
        read_htm_cameras(path, frame=20)


def test_htm_bad_row_names_its_line(tmp_path):
    path = _write(tmp_path, "# header\n0 0 9 1000 1.0 320 10\n")
    with pytest.raises(ConfigError, match="expected 6 or 8 numbers") as caught:
        read_htm_cameras(path)
    assert caught.value.line == 2


# ---------------------------------------------------------------- MPEG-I JSON

JSON_CAMERA = {
    "Name": "v3",
    "Position": [0.5, -0.25, 1.5],
    "Rotation": [30.0, -20.0, 10.0],
    "Depth_range": [0.5, 25.0],
    "Resolution": [1920, 1080],
    "Projection": "Perspective",
    "Focal": [1546.7, 1544.1],
    "Principle_point": [980.5, 550.25],
    "BitDepthColor": 10,
    "BitDepthDepth": 16,
    "ColorSpace": "YUV420",
    "DepthColorSpace": "YUV420",
}


def _euler(yaw, pitch, roll):
    """Rz(yaw) Ry(pitch) Rx(roll), written out independently of the module."""
    a, b, c = np.radians([yaw, pitch, roll])
    rz = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
    ry = np.array([[np.cos(b), 0, np.sin(b)], [0, 1, 0], [-np.sin(b), 0, np.cos(b)]])
    rx = np.array([[1, 0, 0], [0, np.cos(c), -np.sin(c)], [0, np.sin(c), np.cos(c)]])
    return rz @ ry @ rx


def _json_backproject(entry, u, v, d):
    """The MPEG-I formula: camera point (d, -d (u - cx) / fx, -d (v - cy) / fy) in OMAF axes."""
    (fx, fy), (cx, cy) = entry["Focal"], entry["Principle_point"]
    local = np.stack([d, -d * (u - cx) / fx, -d * (v - cy) / fy], axis=-1)
    return local @ _euler(*entry["Rotation"]).T + entry["Position"]


def _write_json(tmp_path, cameras):
    path = tmp_path / "cameras.json"
    path.write_text(json.dumps({"Version": "4.0", "cameras": cameras}))
    return path


def test_json_camera_backprojects_as_the_mpeg_i_formula(tmp_path):
    camera = read_json_cameras(_write_json(tmp_path, [JSON_CAMERA]))["v3"]
    assert camera.size == (1920, 1080) and camera.depth_range == (0.5, 25.0)
    rng = np.random.default_rng(1)
    u, v, d = rng.uniform(0, 1920, 50), rng.uniform(0, 1080, 50), rng.uniform(0.5, 25, 50)
    expected = _json_backproject(JSON_CAMERA, u, v, d)
    # JSON pixel centres are at integer + 0.5, ours at integers: JSON (u, v) is our
    # (u - 0.5, v - 0.5).
    np.testing.assert_allclose(
        backproject(camera, u - 0.5, v - 0.5, d), expected, rtol=0, atol=1e-12
    )
    uv, z = project(camera, expected)
    np.testing.assert_allclose(uv, np.stack([u - 0.5, v - 0.5], axis=-1), rtol=0, atol=1e-9)
    np.testing.assert_allclose(z, d, rtol=1e-13)


def test_json_axes_without_rotation(tmp_path):
    entry = dict(JSON_CAMERA, Rotation=[0, 0, 0], Position=[0, 0, 0])
    camera = read_json_cameras(_write_json(tmp_path, [entry]))["v3"]
    # OMAF: the camera looks along world +x; image right is world -y, image down world -z.
    np.testing.assert_array_equal(camera.optical_axis, [1, 0, 0])
    np.testing.assert_array_equal(camera.R, [[0, -1, 0], [0, 0, -1], [1, 0, 0]])


def test_json_round_trip(tmp_path):
    second = dict(JSON_CAMERA, Name="v4", Rotation=[-170.0, 89.0, -45.0])
    cameras = read_json_cameras(_write_json(tmp_path, [JSON_CAMERA, second]))
    out = tmp_path / "again.json"
    write_json_cameras(out, cameras, video=VideoDescription(bit_depth_color=10, bit_depth_depth=16))
    written = json.loads(out.read_text())["cameras"]
    for original, entry in zip([JSON_CAMERA, second], written):
        np.testing.assert_allclose(entry.pop("Rotation"), original["Rotation"], atol=1e-12)
        assert entry == {
            **{key: value for key, value in original.items() if key != "Rotation"},
            "Depthmap": 1,
            "Background": 0,
            "HasInvalidDepth": False,
        }


@pytest.mark.parametrize(
    "name",
    [
        "cam_param_news.txt",
        "cam_param_lovebird1_original.txt",
        "cam_param_bbb_butterfly2_arc+Znear-far.txt",
    ],
)
def test_text_to_json_to_text_keeps_projections(name, tmp_path):
    cameras = read_cameras(shared_data(*CAMERA_FOLDER, name))
    write_json_cameras(tmp_path / "c.json", cameras, size=(1024, 768))
    write_cameras(tmp_path / "c.txt", read_json_cameras(tmp_path / "c.json"))
    again = read_cameras(tmp_path / "c.txt")
    rng = np.random.default_rng(7)
    for camera_name, camera in cameras.items():
        converted = again[camera_name]
        np.testing.assert_array_equal(converted.K, camera.K)
        np.testing.assert_array_equal(converted.t, camera.t)
        # Yaw/pitch/roll make R exactly orthonormal; the butterfly file's is so to 1e-12.
        np.testing.assert_allclose(converted.R, camera.R, rtol=0, atol=1e-12)
        points = camera.t + rng.normal(size=(20, 3)) * 10 + camera.optical_axis * 100
        for original, reread in zip(project(camera, points), project(converted, points)):
            np.testing.assert_allclose(reread, original, rtol=1e-11, atol=1e-8)


def test_json_errors(tmp_path):
    erp = dict(JSON_CAMERA, Name="erp", Projection="Equirectangular")
    with pytest.raises(ConfigError, match="'Equirectangular' is not supported") as caught:
        read_json_cameras(_write_json(tmp_path, [JSON_CAMERA, erp]))
    assert caught.value.key == "erp"
    broken = {key: value for key, value in JSON_CAMERA.items() if key != "Focal"}
    with pytest.raises(ConfigError, match="Focal must be a list of 2 finite numbers, missing"):
        read_json_cameras(_write_json(tmp_path, [broken]))
    (tmp_path / "bad.json").write_text('{"cameras": [\n{"Name": "a",}\n]}')
    with pytest.raises(ConfigError, match="invalid JSON") as caught:
        read_json_cameras(tmp_path / "bad.json")
    assert caught.value.line == 2
    with pytest.raises(ConfigError, match="'cameras' array"):
        read_json_cameras(_write_json(tmp_path, []))


def test_json_duplicate_name_is_warned(tmp_path, caplog):
    second = dict(JSON_CAMERA, Position=[9.0, 9.0, 9.0])
    with caplog.at_level(logging.WARNING, logger="mvtools"):
        cameras = read_json_cameras(_write_json(tmp_path, [JSON_CAMERA, second]))
    np.testing.assert_array_equal(cameras["v3"].t, [9, 9, 9])
    assert "'v3' is defined again" in caplog.text


def test_json_write_refuses_what_yaw_pitch_roll_cannot_hold(tmp_path):
    skewed = Camera("s", [[1000, 2, 320], [0, 1000, 240], [0, 0, 1]])
    with pytest.raises(UsageError, match="skew"):
        write_json_cameras(tmp_path / "s.json", [skewed])
    mirror = Camera("m", np.diag([1000.0, 1000.0, 1.0]), R=np.diag([-1.0, 1.0, 1.0]))
    with pytest.raises(UsageError, match="not a rotation"):
        write_json_cameras(tmp_path / "s.json", [mirror])
    assert list(tmp_path.iterdir()) == []
