"""VSRS/DERS configuration files, overrides, typed parameters and file lookup."""

import dataclasses
import logging
from pathlib import Path

import pytest
from shared_data import shared_data

from mvtools.errors import ConfigError, UsageError
from mvtools.io.config import (
    COMMAND_LINE,
    DEFAULT,
    ConfigEntry,
    load_params,
    override_entries,
    parse_overrides,
    read_config,
    resolve_input_path,
    resolve_output_path,
    write_config,
)
from mvtools.io.loaded_config import LoadedConfig
from mvtools.params import DersParams, Kind, ParamError, VsrsParams, param_specs

# Values read off the shipped files by eye: (folder, file, SourceWidth, SourceHeight,
# Precision, SynthesisMode, LeftNearestDepthValue, RightFarthestDepthValue, VirtualCameraName).
SHIPPED_VSRS_CONFIGS = [
    ("vsrs_configs", "ViewSynthesis.cfg", 1024, 768, 1, 1, 40.950, 141.044, "param_bd1"),
    (
        "vsrs_configs",
        "ViewSynthesis_book.cfg",
        1024,
        768,
        2,
        1,
        23.344623,
        54.077165,
        "param_book008",
    ),
    # Depth from the world origin with a range behind it: Znear > 0 > Zfar.
    (
        "vsrs_configs",
        "ViewSynthesis_butterfly.cfg",
        1280,
        768,
        4,
        0,
        0.464901,
        -2.491080,
        "param_ptm10",
    ),
    (
        "vsrs_configs",
        "ViewSynthesis_champagne.cfg",
        1280,
        960,
        2,
        1,
        2281.357719,
        7045.261474,
        "param_champ39",
    ),
    (
        "vsrs_configs",
        "ViewSynthesis_dog.cfg",
        1280,
        960,
        2,
        1,
        3907.725727,
        8221.650623,
        "param_dog39",
    ),
    (
        "vsrs_configs",
        "ViewSynthesis_doorflowers.cfg",
        1024,
        768,
        2,
        1,
        20.948175,
        79.056712,
        "param_doorflowers008",
    ),
    (
        "vsrs_configs",
        "ViewSynthesis_laptop.cfg",
        1024,
        768,
        2,
        1,
        23.393445,
        54.440560,
        "param_laptop008",
    ),
    (
        "vsrs_configs",
        "ViewSynthesis_lovebird1.cfg",
        1024,
        768,
        2,
        1,
        1418.292789,
        156012.206895,
        "param_loveb1_006",
    ),
    (
        "vsrs_configs",
        "ViewSynthesis_lovebird2.cfg",
        720,
        576,
        2,
        1,
        3733.743119,
        112012.293585,
        "param_loveb2_006",
    ),
    (
        "vsrs_configs",
        "ViewSynthesis_moabit.cfg",
        1024,
        768,
        2,
        1,
        5.971234,
        189.673574,
        "param_outdoor008",
    ),
    (
        "vsrs_configs",
        "ViewSynthesis_news.cfg",
        1024,
        768,
        2,
        1,
        3393.977060,
        7542.171244,
        "param_news05",
    ),
    (
        "vsrs_configs",
        "ViewSynthesis_pantomime.cfg",
        1280,
        960,
        2,
        1,
        3907.725727,
        8221.650623,
        "param_ptm39",
    ),
    (
        "kendo/config/VSRS",
        "vsrs_kendo_matlab.cfg",
        1024,
        768,
        4,
        0,
        448.251214,
        11206.280350,
        "param_kendo02",
    ),
    (
        "kendo/config/VSRS",
        "vsrs_kendo_matlab2.cfg",
        1024,
        768,
        4,
        0,
        448.251214,
        11206.280350,
        "param_kendo02",
    ),
    (
        "kendo/config/VSRS",
        "vsrs_kendo_matlab_WMGeneration.cfg",
        1024,
        768,
        4,
        0,
        448.251214,
        11206.280350,
        "param_kendo02",
    ),
    (
        "kendo/config/VSRS",
        "vsrs_kendo_ori.cfg",
        1024,
        768,
        4,
        0,
        448.251214,
        11206.280350,
        "param_kendo02",
    ),
]


def write_text(path: Path, text: str, newline: str = "\n") -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(text.replace("\n", newline).encode())
    return path


def load_text(tmp_path, text, cls=VsrsParams, name="test.cfg"):
    """(params, sources, path) of a configuration file holding ``text``."""
    path = write_text(tmp_path / name, text)
    return *load_params(cls, read_config(path)), path


# --- the shipped files ------------------------------------------------------------------


def test_shipped_config_list_is_complete():
    shipped = {
        (folder, path.name)
        for folder, pattern in (("vsrs_configs", "*.cfg"), ("kendo/config/VSRS", "vsrs*.cfg"))
        for path in shared_data("mpeg", *folder.split("/")).glob(pattern)
    }
    assert shipped == {(folder, name) for folder, name, *_ in SHIPPED_VSRS_CONFIGS}


@pytest.mark.parametrize(
    "folder, name, width, height, precision, mode, left_near, right_far, virtual",
    SHIPPED_VSRS_CONFIGS,
    ids=[row[1] for row in SHIPPED_VSRS_CONFIGS],
)
def test_shipped_vsrs_config_parses(
    caplog, folder, name, width, height, precision, mode, left_near, right_far, virtual
):
    path = shared_data("mpeg", *folder.split("/"), name)
    with caplog.at_level(logging.WARNING, logger="mvtools"):
        entries = read_config(path)
        params, _ = load_params(VsrsParams, entries)
    assert caplog.records == []  # every key known, none twice
    assert len(entries) == 24
    assert all("\r" not in entry.value and entry.value for entry in entries.values())
    assert (params.source_width, params.source_height) == (width, height)
    assert (params.precision, params.synthesis_mode) == (precision, mode)
    assert params.left_nearest_depth_value == left_near
    assert params.right_farthest_depth_value == right_far
    assert params.virtual_camera_name == virtual
    assert params.splatting_option == 2 and params.hole_count_threshold == 30  # commented out


def test_kendo_values_sources_and_paths(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # the reference's own first place holds nothing
    mpeg = shared_data("mpeg")
    path = mpeg / "kendo" / "config" / "VSRS" / "vsrs_kendo_ori.cfg"
    params, sources = load_params(VsrsParams, read_config(path))
    assert params.source_width == 1024 and params.source_height == 768
    assert params.precision == 4 and params.view_blending == 1
    assert params.left_depth_range == (448.251214, 11206.280350)
    assert params.right_depth_range == (448.251214, 11206.280350)
    assert params.left_camera_name == "param_kendo01"
    assert params.camera_parameter_file == r"..\data\kendo\config\VSRS\cam_param_kendo.cfg"
    assert params.output_virtual_view_image_name == "kendo_syn_ori.yuv"
    # Absent or commented out in the file: the reference defaults.
    assert (params.splatting_option, params.boundary_growth, params.merging_option) == (2, 40, 2)
    assert (params.depth_threshold, params.depth_blend_difference, params.ivsrs_inpaint) == (
        75,
        5,
        1,
    )
    assert "splatting_option" not in sources

    assert sources["precision"] == ConfigEntry("Precision", "4", str(path), 25)
    loaded = LoadedConfig(params, sources)
    assert loaded.entry("precision").line == 25
    assert loaded.entry("boundary_growth") == ConfigEntry("BoundaryGrowth", "40", DEFAULT, None)

    camera_entry = loaded.entry("camera_parameter_file")
    camera_file = mpeg / "kendo" / "config" / "VSRS" / "cam_param_kendo.cfg"
    for data_dir in (mpeg / "kendo", mpeg):
        assert resolve_input_path(camera_entry, data_dirs=[data_dir]) == camera_file
        assert (
            resolve_input_path(loaded.entry("left_view_image_name"), data_dirs=[data_dir])
            == mpeg / "kendo" / "kendo_ori_I_1.yuv"
        )
        assert (
            resolve_input_path(loaded.entry("right_depth_map_name"), data_dirs=[data_dir])
            == mpeg / "kendo" / "kendo_ori_D_3.yuv"
        )
    # The camera file sits beside the configuration: found with no data folder at all.
    assert resolve_input_path(camera_entry) == camera_file
    with pytest.raises(
        UsageError,
        match=r"vsrs_kendo_ori.cfg:18: LeftViewImageName: .*"
        r"not found \(tried 5 places",
    ):
        resolve_input_path(loaded.entry("left_view_image_name"))


def test_windows_drive_path_found_by_its_tails(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    mpeg = shared_data("mpeg")
    entries = read_config(mpeg / "vsrs_configs" / "ViewSynthesis_book.cfg")
    entry = entries["CameraParameterFile"]  # ../camera_parameter_files/cam_param_book_reg.txt
    assert (
        resolve_input_path(entry, data_dirs=[mpeg / "vsrs_camera_parameters"])
        == mpeg / "vsrs_camera_parameters" / "cam_param_book_reg.txt"
    )

    left = entries["LeftViewImageName"]  # I:\FTV_Test_Sequence\Book_arrival\BookArrival_7.yuv
    data = tmp_path / "sequences"
    write_text(data / "Book_arrival" / "BookArrival_7.yuv", "")
    assert resolve_input_path(left, data_dirs=[data]) == data / "Book_arrival" / "BookArrival_7.yuv"


# --- syntax ------------------------------------------------------------------------------

DERS_TEXT = """\
# DERS configuration\t(hand-written)
DepthType\t\t\t0
SourceWidth   1024   # frame width
SourceHeight\t768#no space before the comment

LeftCameraName        param_kendo01
CenterCameraName      param_kendo02
RightCameraName\t      param_kendo03
FileLeftViewImage     "C:\\My videos\\kendo 1.yuv"   # quoted: holds a space
FileCenterViewImage   kendo_2.yuv
FileOutputDepthMapImage   out\\depth_2.yuv
MinimumValueOfDisparitySearchRange   -5
MaximumValueOfDisparitySearchRange   40
MinimumValueOfDisparityRange   -10
MaximumValueOfDisparityRange   60
SmoothingCoefficient   2.5e0
SearchLevel            0.5
MatchingMethod         3
   # indented comment
MatchDirection         1
"""


def test_ders_config_with_tabs_crlf_and_comments(tmp_path):
    path = write_text(tmp_path / "ders.cfg", DERS_TEXT, newline="\r\n")
    entries = read_config(path)
    assert entries["SourceHeight"] == ConfigEntry("SourceHeight", "768", str(path), 4)
    params, _ = load_params(DersParams, entries)
    assert params.depth_type == 0
    assert (params.source_width, params.source_height) == (1024, 768)
    assert params.center_camera_name == "param_kendo02"
    assert params.right_camera_name == "param_kendo03"
    assert params.file_left_view_image == "C:\\My videos\\kendo 1.yuv"
    assert params.file_output_depth_map_image == "out\\depth_2.yuv"
    assert (
        params.minimum_value_of_disparity_search_range,
        params.maximum_value_of_disparity_search_range,
    ) == (-5, 40)
    assert (params.minimum_value_of_disparity_range, params.maximum_value_of_disparity_range) == (
        -10,
        60,
    )
    assert params.smoothing_coefficient == 2.5 and params.search_level == 0.5
    assert params.matching_method == 3 and params.match_direction == 1
    # Not in the file: DERS 6.1 defaults.
    assert params.file_right_view_image == "" and params.file_camera_parameter == ""
    assert (params.precision, params.filter, params.baseline_basis) == (4, 1, 1)
    assert (params.smoothing_coefficient2, params.temporal_weight) == (1.0, 0.8)
    assert (params.soft_block_width, params.max_cluster, params.total_number_of_frames) == (
        3,
        32,
        300,
    )
    assert params.depth_range is None


def test_key_without_value_is_empty(tmp_path):
    params, _, _ = load_text(tmp_path, "LeftCameraName\nCenterCameraName c  # x\n", DersParams)
    assert params.left_camera_name == "" and params.center_camera_name == "c"


@pytest.mark.parametrize(
    "line, words",
    [
        ("Precision 4 2", 3),
        ("LeftViewImageName D:\\My videos\\left.yuv", 3),
        ("Precision\t4\tquarter pel", 4),
    ],
)
def test_more_than_key_value_is_an_error(tmp_path, line, words):
    path = write_text(tmp_path / "bad.cfg", f"SourceWidth 1024\n\n{line}   # comment\nFilter 1\n")
    with pytest.raises(ConfigError) as info:
        read_config(path)
    assert str(info.value).startswith(f"{path}:3: {line.split()[0]}: {words} words")


def test_unbalanced_quote_is_an_error(tmp_path):
    path = write_text(tmp_path / "bad.cfg", 'SourceWidth 1024\nLeftViewImageName "a b.yuv\n')
    with pytest.raises(ConfigError, match=rf"^{path}:2: unbalanced double quote"):
        read_config(path)


def test_duplicate_key_warns_and_last_wins(tmp_path, caplog):
    with caplog.at_level(logging.WARNING, logger="mvtools"):
        params, sources, path = load_text(tmp_path, "Precision 1\nFilter 0\nPrecision 4\n")
    assert params.precision == 4 and sources["precision"].line == 3
    assert [r.getMessage() for r in caplog.records] == [
        f"{path}:3: Precision given on lines 1 and 3; the last one ('4') wins"
    ]


def test_missing_config_file(tmp_path):
    with pytest.raises(UsageError, match="no such configuration file") as info:
        read_config(tmp_path / "absent.cfg")
    assert not isinstance(info.value, ConfigError)


# --- typed values ------------------------------------------------------------------------


def test_unknown_key_warns_with_nearest_key(tmp_path, caplog):
    with caplog.at_level(logging.WARNING, logger="mvtools"):
        params, _, path = load_text(tmp_path, "SourceWidth 640\nPrecison 4\nZzzz 1\n")
    assert params.precision == 2  # the misspelt key is ignored
    assert [r.getMessage() for r in caplog.records] == [
        f"{path}:2: unknown key 'Precison' (did you mean 'Precision'?), ignored",
        f"{path}:3: unknown key 'Zzzz', ignored",
    ]


@pytest.mark.parametrize(
    "line, message",
    [
        ("SourceWidth abc", "SourceWidth: 'abc' is not an integer"),
        ("SourceWidth 1024.0", "SourceWidth: '1024.0' is not an integer"),
        ("LeftNearestDepthValue 4O.5", "LeftNearestDepthValue: '4O.5' is not a number"),
        ("LeftNearestDepthValue nan", "LeftNearestDepthValue: 'nan' is not a number"),
        ("Precision 3", "Precision: 3 is not one of 1, 2, 4, 8, 16"),
        ("Filter 3", "Filter: 3 is not one of 0, 1, 2"),
        ("HoleCountThreshold 50", "HoleCountThreshold: 50 is outside [0, 49]"),
        ("SourceHeight 0", "SourceHeight: 0 must be >= 1"),
        ("Precision", "Precision: '' is not an integer"),
    ],
)
def test_bad_value_names_file_line_and_key(tmp_path, line, message):
    path = write_text(tmp_path / "bad.cfg", f"SourceWidth 1024\n{line}\n")
    with pytest.raises(ConfigError) as info:
        load_params(VsrsParams, read_config(path))
    assert str(info.value) == f"{path}:2: {message}"


def test_ders_ranges(tmp_path):
    with pytest.raises(
        ConfigError,
        match=r"ders.cfg:1: SearchLevel: 3.0 is not one of "
        r"0.25, 0.5, 1.0, 2.0, 4.0$",
    ):
        load_text(tmp_path, "SearchLevel 3\n", DersParams, "ders.cfg")
    with pytest.raises(ConfigError, match=r"ders.cfg:1: SoftColorCoeff: 0.0 must be > 0$"):
        load_text(tmp_path, "SoftColorCoeff 0\n", DersParams, "ders.cfg")


def test_znear_must_be_nearer_than_zfar(tmp_path):
    text = "DepthType 0\nLeftNearestDepthValue 500\nLeftFarthestDepthValue 400\n"
    with pytest.raises(ConfigError) as info:
        load_text(tmp_path, text)
    assert str(info.value) == (
        f"{tmp_path / 'test.cfg'}:2: LeftNearestDepthValue: Znear 500 is farther than Zfar 400: "
        "need |Znear| < |Zfar| (with LeftFarthestDepthValue 400)"
    )
    with pytest.raises(ConfigError, match="farther than"):
        load_text(tmp_path, "RightNearestDepthValue 7\nRightFarthestDepthValue 7\n")
    # Swapped negative range (Poznan's, written the wrong way round).
    with pytest.raises(
        ConfigError,
        match=r"test.cfg:1: LeftNearestDepthValue: Znear -172.53 is "
        r"farther than Zfar -23.39",
    ):
        load_text(tmp_path, "LeftNearestDepthValue -172.53\nLeftFarthestDepthValue -23.39\n")
    # Only one of the pair given: the other is the default 0 ("not given").
    with pytest.raises(
        ConfigError,
        match=r"test.cfg:1: LeftFarthestDepthValue: "
        r"LeftNearestDepthValue and LeftFarthestDepthValue "
        r"must be given together",
    ):
        load_text(tmp_path, "LeftFarthestDepthValue 400\n")
    with pytest.raises(
        ConfigError,
        match=r"test.cfg:2: LeftNearestDepthValue: Znear -5 and Zfar "
        r"9 have opposite signs: depth along the camera axis",
    ):
        load_text(tmp_path, "DepthType 0\nLeftNearestDepthValue -5\nLeftFarthestDepthValue 9\n")
    # Negative ranges (Poznan Hall 2, DepthType 0; Newspaper, DepthType 1) and a world-z
    # range through 1/z = 0 (Big Buck Bunny butterfly) are VSRS's and accepted.
    for depth_type, near, far in (
        (0, -23.39416, -172.531931),
        (1, -2715.18, -9050.61),
        (1, 0.5, -2.5),
        (1, -0.5, 2.5),
    ):
        params, _, _ = load_text(
            tmp_path,
            f"DepthType {depth_type}\nLeftNearestDepthValue {near}\nLeftFarthestDepthValue {far}\n",
        )
        assert params.left_depth_range == (near, far)
    # The two views must put the scene on one side of the cameras.
    with pytest.raises(
        ConfigError,
        match=r"test.cfg:1: LeftNearestDepthValue: -23.4 and 23.4 "
        r"have opposite signs",
    ):
        load_text(
            tmp_path,
            "LeftNearestDepthValue -23.4\nLeftFarthestDepthValue -172.5\n"
            "RightNearestDepthValue 23.4\nRightFarthestDepthValue 172.5\n",
        )


def test_consistency_between_keys(tmp_path):
    with pytest.raises(ConfigError, match=r"test.cfg:2: ColorSpace: the 1D mode"):
        load_text(tmp_path, "SynthesisMode 1\nColorSpace 1\n")
    with pytest.raises(
        ConfigError,
        match=r"test.cfg:1: MaximumValueOfDisparitySearchRange: 30 "
        r"is above MaximumValueOfDisparityRange 20",
    ):
        load_text(tmp_path, "MaximumValueOfDisparitySearchRange 30\n", DersParams)
    with pytest.raises(
        ConfigError,
        match=r"test.cfg:1: MaximumValueOfDisparityRange: .*"
        r"gives 401 depth values",
    ):
        load_text(tmp_path, "MaximumValueOfDisparityRange 200\n", DersParams)
    with pytest.raises(
        ConfigError,
        match=r"test.cfg:2: DepthEstimationMode: mode 3 \(from a "
        r"reference depth\) is not supported",
    ):
        load_text(tmp_path, "RefDepthCameraName cam0\nDepthEstimationMode 3\n", DersParams)


def test_direct_construction_validates():
    with pytest.raises(ParamError, match=r"^Precision: 3 is not one of 1, 2, 4, 8, 16$"):
        VsrsParams(precision=3)
    with pytest.raises(ValueError, match=r"^SourceWidth: 1.5 is not an integer$"):
        VsrsParams(source_width=1.5)
    params = VsrsParams(
        left_nearest_depth_value=1,
        left_farthest_depth_value=2,
        left_view_image_name=Path("a") / "b.yuv",
    )
    assert params.left_nearest_depth_value == 1.0 and type(params.left_nearest_depth_value) is float
    assert params.left_view_image_name == str(Path("a") / "b.yuv")
    assert dataclasses.replace(params, precision=4).precision == 4


# --- command line ------------------------------------------------------------------------


def test_overrides_win_over_the_file(tmp_path):
    path = write_text(tmp_path / "test.cfg", "Precision 1\nSourceWidth 640\n")
    entries = read_config(path)
    entries.update(parse_overrides(["Precision=4", "LeftViewImageName=a b.yuv"]))
    params, sources = load_params(VsrsParams, entries)
    assert (params.precision, params.source_width) == (4, 640)
    assert params.left_view_image_name == "a b.yuv"
    assert sources["precision"] == ConfigEntry("Precision", "4", COMMAND_LINE, None)
    assert sources["source_width"].path == str(path)
    with pytest.raises(ConfigError, match=r"^<command line>: Precision: 3 is not one of"):
        load_params(VsrsParams, {**entries, **parse_overrides(["Precision=3"])})
    with pytest.raises(ConfigError, match=r"^<command line>: Filter: '' is not an integer"):
        load_params(VsrsParams, {**entries, **parse_overrides(["Filter="])})


@pytest.mark.parametrize("item", ["Precision", "=4", "Pre cision=4"])
def test_malformed_override(item):
    with pytest.raises(UsageError, match=rf"^<command line>: malformed setting '{item}'"):
        parse_overrides([item])


def test_option_values_become_command_line_entries():
    entries = override_entries(
        VsrsParams, {"precision": 1, "left_nearest_depth_value": 0.1, "filter": None}
    )
    assert entries == {
        "Precision": ConfigEntry("Precision", "1", COMMAND_LINE, None),
        "LeftNearestDepthValue": ConfigEntry("LeftNearestDepthValue", "0.1", COMMAND_LINE, None),
    }


def test_param_specs_metadata():
    specs = {spec.key: spec for spec in param_specs(VsrsParams)}
    assert len(specs) == 34 and len(param_specs(DersParams)) == 50
    precision = specs["Precision"]
    assert (precision.name, precision.type, precision.default, precision.choices) == (
        "precision",
        int,
        2,
        (1, 2, 4, 8, 16),
    )
    near = specs["LeftNearestDepthValue"]
    assert (near.name, near.type, near.default) == ("left_nearest_depth_value", float, 0.0)
    assert {key for key, spec in specs.items() if spec.kind is Kind.INPUT_FILE} == {
        "CameraParameterFile",
        "LeftViewImageName",
        "RightViewImageName",
        "LeftDepthMapName",
        "RightDepthMapName",
    }
    assert specs["OutputVirtualViewImageName"].kind is Kind.OUTPUT_FILE
    ders = {spec.key: spec for spec in param_specs(DersParams)}
    assert ders["FileOutputDepthMapImage"].kind is Kind.OUTPUT_FILE
    assert (ders["SmoothingCoefficient"].default, ders["MatchDirection"].choices) == (
        4.0,
        (1, 2, 3),
    )


# --- file lookup -------------------------------------------------------------------------


def test_missing_input_lists_every_place_tried(tmp_path, monkeypatch):
    work = tmp_path / "work"
    work.mkdir()
    monkeypatch.chdir(work)
    config = write_text(
        tmp_path / "cfg" / "v.cfg", "SourceWidth 64\nLeftViewImageName ..\\seq\\left.yuv\n"
    )
    entry = read_config(config)["LeftViewImageName"]
    data = tmp_path / "data"
    with pytest.raises(UsageError) as info:
        resolve_input_path(entry, data_dirs=[data])
    message = str(info.value)
    assert message.startswith(
        f"{config}:2: LeftViewImageName: file '..\\seq\\left.yuv' not found (tried 7 places: "
    )
    tried = [
        work / ".." / "seq" / "left.yuv",
        tmp_path / "cfg" / ".." / "seq" / "left.yuv",
        tmp_path / "cfg" / "seq" / "left.yuv",
        tmp_path / "cfg" / "left.yuv",
        data / ".." / "seq" / "left.yuv",
        data / "seq" / "left.yuv",
        data / "left.yuv",
    ]
    assert ", ".join(map(str, tried)) in message

    # Found where the path points from the current folder, as the reference does.
    write_text(data / "left.yuv", "")
    assert resolve_input_path(entry, data_dirs=[data]) == data / "left.yuv"
    write_text(tmp_path / "cfg" / "seq" / "left.yuv", "")
    assert resolve_input_path(entry, data_dirs=[data]) == tmp_path / "cfg" / "seq" / "left.yuv"
    write_text(tmp_path / "seq" / "left.yuv", "")
    assert resolve_input_path(entry, data_dirs=[data]) == work / ".." / "seq" / "left.yuv"


def test_input_from_command_line_and_not_required(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    entry = parse_overrides(["CameraParameterFile=cams\\cam.txt"])["CameraParameterFile"]
    with pytest.raises(
        UsageError, match=r"^<command line>: CameraParameterFile: .*tried 1 place: "
    ):
        resolve_input_path(entry)
    assert resolve_input_path(entry, must_exist=False) == tmp_path / "cams" / "cam.txt"
    with pytest.raises(UsageError, match="no file name given"):
        resolve_input_path(ConfigEntry("LeftViewImageName", "", COMMAND_LINE, None))


def test_output_path(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "out").mkdir()
    assert resolve_output_path(
        ConfigEntry("FileOutputDepthMapImage", "out\\d.yuv", "x.cfg", 3)
    ) == Path("out", "d.yuv")
    with pytest.raises(
        UsageError,
        match=r"^x.cfg:3: OutputVirtualViewImageName: absent: the "
        r"output folder does not exist$",
    ):
        resolve_output_path(ConfigEntry("OutputVirtualViewImageName", "absent\\v.yuv", "x.cfg", 3))
    with pytest.raises(UsageError, match="Windows drive path"):
        resolve_output_path(ConfigEntry("OutputVirtualViewImageName", "I:\\v.yuv", "x.cfg", 3))


# --- writing -----------------------------------------------------------------------------


def test_write_config_round_trip(tmp_path):
    params = VsrsParams(
        depth_type=1,
        source_width=1920,
        source_height=1080,
        precision=4,
        filter=2,
        left_nearest_depth_value=0.1 + 0.2,
        left_farthest_depth_value=-2.424092,
        right_nearest_depth_value=1e-3,
        right_farthest_depth_value=-1e300,
        camera_parameter_file="C:\\My cams\\cam #1.txt",
        left_camera_name="",
        virtual_camera_name="v",
        left_view_image_name="left.yuv",
        output_virtual_view_image_name="out\\syn.yuv",
        hole_count_threshold=49,
    )
    path = tmp_path / "written.cfg"
    write_config(path, params)
    lines = path.read_text().splitlines()
    assert lines[0].startswith("# VSRS configuration written by mvtools")
    by_key = {line.split()[0]: line for line in lines[1:]}
    assert len(by_key) == 34
    assert by_key["Precision"].split("#")[0].split() == ["Precision", "4"]
    assert by_key["Precision"].endswith(
        "# horizontal upsampling of the references, 1: integer, 2: half, 4: quarter pixel; "
        "8, 16: eighth, sixteenth pixel (mvtools extensions)"
    )
    assert by_key["LeftCameraName"].split("#")[0].split() == ["LeftCameraName"]
    assert '"C:\\My cams\\cam #1.txt"' in by_key["CameraParameterFile"]
    assert len({line.index("#") for line in lines[1:] if '"' not in line}) == 1  # aligned
    again, _ = load_params(VsrsParams, read_config(path))
    assert again == params
    assert again.left_nearest_depth_value == 0.1 + 0.2

    ders = DersParams(
        search_level=0.5,
        minimum_value_of_disparity_range=-3,
        nearest_depth_value=10.5,
        farthest_depth_value=100.25,
    )
    write_config(path, ders)
    assert load_params(DersParams, read_config(path))[0] == ders


def test_write_config_refuses_unwritable_value(tmp_path):
    path = tmp_path / "written.cfg"
    with pytest.raises(UsageError, match=r"LeftCameraName: .* cannot be written"):
        write_config(path, VsrsParams(left_camera_name='a "b" c'))
    assert not path.exists()


@pytest.mark.parametrize(
    "name, cls", [("vsrs_defaults.cfg", VsrsParams), ("ders_defaults.cfg", DersParams)]
)
def test_shipped_templates_hold_every_key_with_its_default(name, cls):
    template = Path(__file__).resolve().parent.parent / "configs" / name
    entries = read_config(template)
    assert set(entries) == {spec.key for spec in param_specs(cls)}
    assert load_params(cls, entries)[0] == cls()


def test_method_key_offers_exactly_the_depth_methods():
    from mvtools.depth import METHODS, PAIR_METHODS

    spec = next(spec for spec in param_specs(DersParams) if spec.key == "Method")
    assert set(spec.choices) == set(PAIR_METHODS) and spec.default in METHODS
