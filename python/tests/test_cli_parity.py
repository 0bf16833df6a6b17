"""The module and the gdm command run one pipeline: the same mesh, bit for bit."""
import json
import re
import math

import numpy as np
import pytest

import gdm
from conftest import SOURCE, PHANTOM, TOOTH, need, parse_obj, read_metaimage


def same_mesh(result, obj_path):
    vertices, faces = parse_obj(obj_path)  # 17 significant digits: doubles read back exactly
    assert result.vertices.dtype == np.float64 and result.faces.dtype == np.int32
    assert result.vertices.shape == vertices.shape and result.faces.shape == faces.shape
    assert np.array_equal(result.vertices, vertices)
    assert np.array_equal(result.faces, faces)


def test_phantom_same_mesh_as_the_command(cli, tmp_path):
    cli(PHANTOM, "--threshold", 400, "-o", tmp_path / "cli.obj", "--report", tmp_path / "cli.json", "--quiet")
    cli(PHANTOM, "--threshold", 400, "-o", tmp_path / "cli.ply", "--quiet")
    volume, spacing, origin, direction = gdm.read_image(PHANTOM)
    result = gdm.extract_surface(volume, spacing, origin, direction, threshold=400)
    same_mesh(result, tmp_path / "cli.obj")
    assert len(result.faces) == 3918  # the README's figure
    # gdm.write_mesh writes the command's bytes
    gdm.write_mesh(tmp_path / "py.obj", result)
    gdm.write_mesh(tmp_path / "py.ply", result)
    assert (tmp_path / "py.obj").read_bytes() == (tmp_path / "cli.obj").read_bytes()
    assert (tmp_path / "py.ply").read_bytes() == (tmp_path / "cli.ply").read_bytes()

    # the report: the command's JSON sections, same values
    report = json.loads((tmp_path / "cli.json").read_text())
    assert result.report["threshold"] == report["threshold"]
    assert result.report["seed"] == report["seed"]
    assert result.report["mesh"] == report["mesh"]
    model = dict(result.report["model"])
    cli_model = dict(report["model"])
    model.pop("seconds"), cli_model.pop("seconds")
    # stage times: the same steps, each a duration (values differ run to run)
    stages, cli_stages = model.pop("stage_seconds"), cli_model.pop("stage_seconds")
    assert sorted(stages) == sorted(cli_stages)
    assert all(stages[k] >= 0.0 and cli_stages[k] >= 0.0 for k in stages)
    assert cli_stages["growth"] > 0.0 and stages["growth"] > 0.0
    assert model == cli_model
    for option in gdm.options():
        name = option["name"]
        mine, theirs = result.report["parameters"][name], report["parameters"][name]
        if isinstance(mine, float) and math.isinf(mine):
            mine = "inf"
        assert mine == theirs, name
    assert result.report["parameters"]["threshold"] == 400
    assert result.report["status"] == "ok"


def test_phantom_array_read_with_numpy_alone(cli, tmp_path):
    """The phantom's voxels read with numpy (x fastest in the file) give the same mesh."""
    cli(PHANTOM, "--threshold", 400, "-o", tmp_path / "cli.obj", "--quiet")
    array, spacing, origin = read_metaimage(PHANTOM)  # int16, Fortran-ordered view of the file
    assert array.dtype == np.int16 and array.flags.f_contiguous
    result = gdm.extract_surface(array, spacing, origin, threshold=400)
    same_mesh(result, tmp_path / "cli.obj")


def test_tooth_pulp_from_a_numpy_array(cli, tmp_path):
    need(TOOTH, "the tooth (../shared/data/tooth/tooth.mhd)")
    cli(TOOTH, "--threshold", 115, "--polarity", "dark", "--seed-index", "50,47,95", "-o", tmp_path / "cli.obj",
        "--report", tmp_path / "cli.json", "--quiet")
    array, spacing, origin = read_metaimage(TOOTH)  # uint8, 103 x 94 x 161, 1 mm, origin 0
    assert array.shape == (103, 94, 161) and spacing == (1, 1, 1) and origin == (0, 0, 0)
    # voxel (50, 47, 95) is the point (50, 47, 95) mm
    by_point = gdm.extract_surface(array, spacing, origin, threshold=115, polarity="dark", seed=(50, 47, 95))
    same_mesh(by_point, tmp_path / "cli.obj")
    by_index = gdm.extract_surface(array, spacing, origin, threshold=115, polarity="dark", seed_index=(50, 47, 95))
    same_mesh(by_index, tmp_path / "cli.obj")
    # a C-ordered float64 copy of the same voxels: the same mesh
    c_order = np.ascontiguousarray(array, dtype=np.float64)
    assert c_order.flags.c_contiguous and not c_order.flags.f_contiguous
    same_mesh(gdm.extract_surface(c_order, spacing, origin, threshold=115, polarity="dark", seed=(50, 47, 95)),
              tmp_path / "cli.obj")
    report = json.loads((tmp_path / "cli.json").read_text())
    assert by_point.report["mesh"] == report["mesh"]
    # the README's figure at the default level of detail (its tooth pulp table)
    table_row = re.search(r"^\| defaults \(`--lod 10`\) \| (\d+) \|", (SOURCE / "README.md").read_text(), re.M)
    assert table_row and by_point.report["mesh"]["faces"] == int(table_row.group(1))
    assert by_point.report["mesh"]["closed"] and by_point.report["mesh"]["genus"] == 0
