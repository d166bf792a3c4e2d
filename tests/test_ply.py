"""PLY files: ours read by an independent reader (plyfile), plyfile's read by ours, and
every kind of damaged file refused with a one-line message."""

from __future__ import annotations

import numpy as np
import plyfile
import pytest

from mvtools.errors import ConfigError, DataError, UsageError
from mvtools.io.ply import read_ply, write_ply

RNG = np.random.default_rng(19)
POINTS = RNG.normal(scale=100.0, size=(50, 3))
COLORS = RNG.integers(0, 256, size=(50, 3)).astype(np.uint8)


def _plyfile_arrays(path):
    vertex = plyfile.PlyData.read(str(path))["vertex"]
    points = np.stack([vertex[name] for name in "xyz"], axis=-1)
    colors = np.stack([vertex[name] for name in ("red", "green", "blue")], axis=-1)
    return vertex, points, colors


@pytest.mark.parametrize(("precision", "dtype"), [("single", np.float32), ("double", np.float64)])
def test_plyfile_reads_what_we_write(tmp_path, precision, dtype):
    path = tmp_path / "cloud.ply"
    write_ply(path, POINTS, COLORS, precision=precision)
    vertex, points, colors = _plyfile_arrays(path)
    assert vertex.count == 50
    assert points.dtype == dtype
    np.testing.assert_array_equal(points, POINTS.astype(dtype))
    np.testing.assert_array_equal(colors, COLORS)
    assert colors.dtype == np.uint8
    assert path.read_bytes().startswith(b"ply\nformat binary_little_endian 1.0\n")


def test_an_empty_cloud_round_trips(tmp_path):
    path = tmp_path / "empty.ply"
    write_ply(path, np.zeros((0, 3)), np.zeros((0, 3), np.uint8))
    points, colors = read_ply(path)
    assert points.shape == (0, 3) and colors.shape == (0, 3)
    assert plyfile.PlyData.read(str(path))["vertex"].count == 0


def _plyfile_cloud(path, *, text, byte_order):
    """A cloud written by plyfile: properties in another order, extra ones, integer y,
    and a face element with a list property before the vertices."""
    vertex = np.empty(
        len(POINTS),
        [
            ("nx", "f4"),
            ("z", "f8"),
            ("blue", "u1"),
            ("x", "f4"),
            ("y", "i4"),
            ("alpha", "u1"),
            ("red", "u1"),
            ("green", "u1"),
        ],
    )
    vertex["x"], vertex["y"], vertex["z"] = POINTS[:, 0], np.round(POINTS[:, 1]), POINTS[:, 2]
    vertex["red"], vertex["green"], vertex["blue"] = COLORS.T
    vertex["nx"], vertex["alpha"] = 0.5, 255
    faces = np.empty(3, [("vertex_indices", "i4", (3,))])
    faces["vertex_indices"] = [[0, 1, 2], [2, 3, 4], [4, 5, 6]]
    elements = [
        plyfile.PlyElement.describe(faces, "face"),
        plyfile.PlyElement.describe(vertex, "vertex"),
    ]
    plyfile.PlyData(elements, text=text, byte_order=byte_order).write(str(path))
    return vertex


@pytest.mark.parametrize(
    ("text", "byte_order"),
    [(True, "="), (False, "<"), (False, ">")],
    ids=["ascii", "binary_little_endian", "binary_big_endian"],
)
def test_we_read_what_plyfile_writes(tmp_path, text, byte_order):
    path = tmp_path / "theirs.ply"
    vertex = _plyfile_cloud(path, text=text, byte_order=byte_order)
    points, colors = read_ply(path)
    assert points.dtype == np.float64 and colors.dtype == np.uint8
    expected = np.stack([vertex["x"], vertex["y"], vertex["z"]], axis=-1).astype(np.float64)
    if text:
        # plyfile prints floats with repr of float32 and float64: the same numbers
        np.testing.assert_allclose(points, expected, rtol=1e-7)
    else:
        np.testing.assert_array_equal(points, expected)
    np.testing.assert_array_equal(colors, COLORS)


def _header(*lines, fmt="binary_little_endian"):
    return ("\n".join(["ply", f"format {fmt} 1.0", *lines, "end_header"]) + "\n").encode()


VERTEX = [
    "element vertex 5000",
    *(f"property float {a}" for a in "xyz"),
    *(f"property uchar {c}" for c in ("red", "green", "blue")),
]


def test_truncated_binary_data_names_the_vertex(tmp_path):
    path = tmp_path / "short.ply"
    path.write_bytes(_header(*VERTEX) + bytes(15 * 1234 + 7))
    with pytest.raises(DataError) as error:
        read_ply(path)
    assert str(error.value) == f"{path}: vertex 1234 of 5000: file ends"
    assert error.value.exit_code == 1


def test_an_ascii_line_with_missing_fields_names_the_line(tmp_path):
    path = tmp_path / "missing.ply"
    header = _header("comment two vertices", *VERTEX, fmt="ascii").replace(b"5000", b"2")
    path.write_bytes(header + b"0 0 1 255 0 0\n1 2 3 4\n")
    with pytest.raises(DataError) as error:
        read_ply(path)
    # header of 11 lines, vertex 0 on line 12, vertex 1 on line 13
    assert error.value.line == 13 and error.value.key == "green"
    assert str(error.value).startswith(f"{path}:13: green: vertex 1 of 2 has 4 of 6 fields")


def test_an_ascii_field_that_is_no_number_names_the_line(tmp_path):
    path = tmp_path / "word.ply"
    header = _header(*VERTEX, fmt="ascii").replace(b"5000", b"1")
    path.write_bytes(header + b"0 zero 1 255 0 0\n")
    with pytest.raises(DataError, match="'zero' is not a number") as error:
        read_ply(path)
    assert (error.value.line, error.value.key) == (11, "y")  # 10 header lines


def test_ascii_data_that_ends_early(tmp_path):
    path = tmp_path / "few.ply"
    path.write_bytes(_header(*VERTEX, fmt="ascii") + b"0 0 1 255 0 0\n")
    with pytest.raises(DataError, match="vertex 1 of 5000: file ends"):
        read_ply(path)


def test_no_colour_property_is_a_config_error_naming_it(tmp_path):
    path = tmp_path / "grey.ply"
    path.write_bytes(_header(*[line for line in VERTEX if "red" not in line]))
    with pytest.raises(ConfigError) as error:
        read_ply(path)
    assert error.value.key == "red" and error.value.exit_code == 2
    assert "no red property" in str(error.value)


def test_not_a_ply_file(tmp_path):
    path = tmp_path / "cloud.ply"
    path.write_bytes(b"OFF\n3 1 0\n")
    with pytest.raises(ConfigError) as error:
        read_ply(path)
    assert error.value.line == 1 and "not a PLY file" in str(error.value)


@pytest.mark.parametrize(
    ("line", "number", "message"),
    [
        ("property float32x x", 4, "a property line is"),
        ("element vertex many", 3, "an element line is"),
        ("colour red", 3, "unknown header line"),
    ],
)
def test_a_bad_header_line_is_named(tmp_path, line, number, message):
    path = tmp_path / "bad.ply"
    lines = list(VERTEX)
    lines.insert(number - 3, line)
    path.write_bytes(_header(*lines))
    with pytest.raises(ConfigError, match=message) as error:
        read_ply(path)
    assert error.value.line == number


def test_a_bad_format_line(tmp_path):
    path = tmp_path / "bad.ply"
    path.write_bytes(_header(*VERTEX, fmt="binary_middle_endian"))
    with pytest.raises(ConfigError, match="format must be") as error:
        read_ply(path)
    assert error.value.line == 2


def test_a_header_without_end(tmp_path):
    path = tmp_path / "open.ply"
    path.write_bytes(b"ply\nformat ascii 1.0\nelement vertex 1\n")
    with pytest.raises(ConfigError, match="no end_header") as error:
        read_ply(path)
    assert error.value.line == 4


def test_a_missing_file(tmp_path):
    with pytest.raises(UsageError, match="no such file"):
        read_ply(tmp_path / "none.ply")


def test_write_refuses_bad_arrays_and_leaves_nothing(tmp_path):
    path = tmp_path / "bad.ply"
    with pytest.raises(ValueError, match="shape"):
        write_ply(path, np.zeros((3, 2)), np.zeros((3, 2), np.uint8))
    with pytest.raises(ValueError, match=r"0\.\.255"):
        write_ply(path, np.zeros((1, 3)), [[0, 0, 256]])
    assert list(tmp_path.iterdir()) == []
