"""Every camera and configuration file of the published MPEG material loads, whatever
its kind (VSRS/HTM camera files, VSRS and 3D-HTM configurations)."""

from __future__ import annotations

import pytest
from shared_data import data_root, shared_data

from mvtools.io.cameras import read_cameras, read_htm_cameras
from mvtools.io.config import load_params, read_config, read_htm_config
from mvtools.params import VsrsParams


def _published_files():
    mpeg = data_root() / "mpeg"
    if not mpeg.exists():
        return ["(missing)"]
    return sorted(
        str(path.relative_to(mpeg))
        for path in mpeg.rglob("*")
        if path.suffix in (".cfg", ".txt") and not path.name.startswith("MANIFEST")
    )


def _load(path):
    name = path.name
    if path.parent.name == "HTM":
        return read_htm_cameras(path) if name.startswith("cam") else read_htm_config(path)
    if name.startswith("cam_param"):
        return read_cameras(path)
    return load_params(VsrsParams, read_config(path))[0]


@pytest.mark.parametrize("relative", _published_files())
def test_every_camera_and_config_file_loads(relative):
    loaded = _load(shared_data("mpeg", *relative.split("/")))
    assert loaded


def test_published_file_count():
    # The folder's manifests list 23 VSRS camera files, 12 VSRS configs, the Kendo set's
    # 7 files and Poznan Hall 2's 19 (its camera file, 16 VSRS configurations and 2 HTM
    # files): negative depth ranges among them.
    files = _published_files()
    counts = {"vsrs_camera_parameters/": 23, "vsrs_configs/": 12, "kendo/": 7, "poznan_hall2/": 19}
    for folder, count in counts.items():
        assert sum(name.startswith(folder) for name in files) == count, folder
    assert len(files) == sum(counts.values())


def test_htm_configuration_values():
    entries = read_htm_config(shared_data("mpeg", "kendo", "config", "HTM", "HTM_cfg_kendo.cfg"))
    assert entries["SourceWidth"].value == "1024" and entries["SourceHeight"].value == "768"
    assert entries["InputBitDepth"].value == "8"
    assert entries["Frame1"].value.split()[:3] == ["B", "8", "1"]
