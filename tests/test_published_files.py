"""Every camera and configuration file of the published MPEG material loads, whatever
its kind (VSRS/HTM camera files, VSRS and 3D-HTM configurations)."""

from __future__ import annotations

import pytest

from mvtools.io.cameras import read_cameras, read_htm_cameras
from mvtools.io.config import load_params, read_config, read_htm_config
from mvtools.params import VsrsParams
from shared_data import data_root, shared_data


def _published_files():
    mpeg = data_root() / "mpeg"
    if not mpeg.exists():
        return ["(missing)"]
    return sorted(str(path.relative_to(mpeg)) for path in mpeg.rglob("*")
                  if path.suffix in (".cfg", ".txt") and not path.name.startswith("MANIFEST"))


def _load(path):
    name = path.name
    if path.parent.name == "HTM":
        return read_htm_cameras(path) if name.startswith("cam") else read_htm_config(path)
    if name.startswith("cam_param"):
        return read_cameras(path)
    return load_params(VsrsParams, read_config(path))


@pytest.mark.parametrize("relative", _published_files())
def test_every_camera_and_config_file_loads(relative):
    loaded = _load(shared_data("mpeg", *relative.split("/")))
    assert loaded


def test_published_file_count():
    # The folder's manifest lists 23 VSRS camera files, 12 VSRS configs and the Kendo set.
    files = _published_files()
    assert sum(name.startswith("vsrs_camera_parameters/") for name in files) == 23
    assert sum(name.startswith("vsrs_configs/") for name in files) == 12
    assert len(files) == 23 + 12 + 7


def test_htm_configuration_values():
    entries = read_htm_config(shared_data("mpeg", "kendo", "config", "HTM", "HTM_cfg_kendo.cfg"))
    assert entries["SourceWidth"].value == "1024" and entries["SourceHeight"].value == "768"
    assert entries["InputBitDepth"].value == "8"
    assert entries["Frame1"].value.split()[:3] == ["B", "8", "1"]
