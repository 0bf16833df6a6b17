"""Every bad input is a clear, typed exception (never a crash)."""
import numpy as np
import pytest

import gdm
from conftest import icosphere, sphere


@pytest.fixture(scope="module")
def ball():
    volume, center = sphere(24, radius=7.0)
    return volume, center


def test_exception_classes():
    for cls in (gdm.InvalidOption, gdm.InvalidVolume, gdm.InvalidSeed):
        assert issubclass(cls, ValueError) and issubclass(cls, gdm.Error)
    assert issubclass(gdm.InvalidInput, OSError) and issubclass(gdm.InvalidInput, gdm.Error)
    assert issubclass(gdm.ModelFailed, RuntimeError) and issubclass(gdm.ModelFailed, gdm.Error)
    assert issubclass(gdm.Cancelled, gdm.Error) and not issubclass(gdm.Cancelled, gdm.ModelFailed)


def test_wrong_ndim(ball):
    with pytest.raises(gdm.InvalidVolume, match="3D array.*got 2 dimensions"):
        gdm.extract_surface(ball[0][:, :, 0], threshold=50)
    with pytest.raises(gdm.InvalidVolume, match="got 4 dimensions"):
        gdm.extract_surface(ball[0][..., None], threshold=50)


def test_nan_and_inf(ball):
    v = ball[0].copy(order="F")
    v[3, 4, 5] = np.nan
    with pytest.raises(gdm.InvalidVolume, match="NaN"):
        gdm.extract_surface(v, threshold=50)
    v[3, 4, 5] = np.inf
    with pytest.raises(gdm.InvalidVolume, match="infinite"):
        gdm.extract_surface(v, threshold=50)


@pytest.mark.parametrize("spacing", [(0, 1, 1), (1, -1, 1), (1, 1, float("nan"))])
def test_bad_spacing(ball, spacing):
    with pytest.raises(gdm.InvalidVolume, match="spacing"):
        gdm.extract_surface(ball[0], spacing, threshold=50)


def test_bad_geometry_arguments(ball):
    with pytest.raises(gdm.InvalidOption, match="spacing must be 3 numbers"):
        gdm.extract_surface(ball[0], (1, 1), threshold=50)
    with pytest.raises(gdm.InvalidVolume, match="direction must be a 3x3"):
        gdm.extract_surface(ball[0], direction=np.eye(2), threshold=50)
    with pytest.raises(gdm.InvalidVolume, match="direction.*singular"):
        gdm.extract_surface(ball[0], direction=np.zeros((3, 3)), threshold=50)


def test_empty_and_tiny():
    with pytest.raises(gdm.InvalidVolume, match="empty"):
        gdm.extract_surface(np.zeros((0, 5, 5)), threshold=1)
    with pytest.raises(gdm.InvalidVolume, match="constant"):
        gdm.extract_surface(np.zeros((5, 5, 5)))
    with pytest.raises(gdm.InvalidVolume, match="dimension"):
        gdm.extract_surface(np.zeros((1, 5, 5)), threshold=1)


def test_not_real_numbers():
    with pytest.raises(TypeError, match="real numbers.*complex"):
        gdm.extract_surface(np.zeros((4, 4, 4), dtype=complex))
    with pytest.raises(TypeError, match="real numbers"):
        gdm.extract_surface(np.array([[["a"]]]))
    with pytest.raises(TypeError, match="None"):
        gdm.extract_surface(None)


@pytest.mark.parametrize("keyword, value, pattern", [
    ("a2", -1, r"a2 must be >= 0, got -1"),
    ("lod_face_area", 0.1, r"lod_face_area must be >= 0.5"),
    ("global_refinements", 1.5, r"global_refinements must be in \[0, 4\]"),
    ("max_cycles", "many", r"max_cycles must be"),
    ("polarity", "brighter", r"polarity must be bright or dark, got 'brighter'"),
    ("subvoxel_fit", 2, r"subvoxel_fit must be on or off"),
    ("a0", float("nan"), r"a0 must be > 0"),
    ("smooth", True, r"smooth must be"),
])
def test_bad_option_value_names_it(ball, keyword, value, pattern):
    with pytest.raises(gdm.InvalidOption, match=pattern) as e:
        gdm.extract_surface(ball[0], threshold=50, **{keyword: value})
    assert e.value.option == keyword
    assert isinstance(e.value, ValueError)


def test_unknown_keyword(ball):
    with pytest.raises(TypeError, match="unexpected keyword argument 'lod'; did you mean 'lod_face_area'"):
        gdm.extract_surface(ball[0], threshold=50, lod=4)
    with pytest.raises(TypeError, match="did you mean 'polarity'"):
        gdm.extract_surface(ball[0], threshold=50, polarty="dark")


def test_bad_threshold(ball):
    with pytest.raises(gdm.InvalidOption, match="outside the value range") as e:
        gdm.extract_surface(ball[0], threshold=1000)
    assert e.value.option == "threshold"
    with pytest.raises(gdm.InvalidOption, match="threshold must be"):
        gdm.extract_surface(ball[0], threshold="half")
    with pytest.raises(gdm.InvalidOption, match="finite"):
        gdm.extract_surface(ball[0], threshold=float("nan"))


def test_seed_outside(ball):
    with pytest.raises(gdm.InvalidSeed, match=r"outside the volume"):
        gdm.extract_surface(ball[0], threshold=50, seed=(100, 0, 0))
    with pytest.raises(gdm.InvalidSeed, match="not inside the object"):
        gdm.extract_surface(ball[0], threshold=50, seed=(4, 4, 4))
    with pytest.raises(gdm.InvalidSeed, match="outside"):
        gdm.extract_surface(ball[0], threshold=50, seed_index=(-3, 5, 5))
    with pytest.raises(gdm.InvalidOption, match="seed must be"):
        gdm.extract_surface(ball[0], threshold=50, seed="center")
    with pytest.raises(gdm.InvalidOption, match="seed must be"):
        gdm.extract_surface(ball[0], threshold=50, seed=(1, 2, 3, 4))
    with pytest.raises(gdm.InvalidOption, match="either seed or seed_index"):
        gdm.extract_surface(ball[0], threshold=50, seed=(1, 2, 3), seed_index=(1, 2, 3))


def test_bad_seed_mesh(ball):
    tetra_v = np.array([[10, 10, 10], [13, 10, 10], [10, 13, 10], [10, 10, 13]], float)
    with pytest.raises(gdm.InvalidSeed, match="refers to a vertex outside"):
        gdm.extract_surface(ball[0], threshold=50, seed=(tetra_v, [[0, 1, 7]]))
    with pytest.raises(gdm.InvalidSeed, match="vertices must be an N x 3"):
        gdm.extract_surface(ball[0], threshold=50, seed=(np.zeros((4, 2)), [[0, 1, 2]]))
    with pytest.raises(gdm.InvalidSeed):  # open: one face of the tetrahedron
        gdm.extract_surface(ball[0], threshold=50, seed=(tetra_v, [[0, 2, 1]]))
    # a closed geodesic sphere around the centre: the same mesh as the point seed of that radius
    r = gdm.extract_surface(ball[0], threshold=50, seed=icosphere(ball[1], 3.0, 1))
    assert r.report["seed"]["source"] == "mesh" and r.report["mesh"]["closed"]
    p = gdm.extract_surface(ball[0], threshold=50, seed=tuple(ball[1]), seed_radius=3.0)
    assert abs(r.report["mesh"]["volume_mm3"] / p.report["mesh"]["volume_mm3"] - 1) < 0.01


def test_model_failed_says_why(ball):
    """Dark polarity from the background: the model leaks to the border."""
    with pytest.raises(gdm.ModelFailed, match="reached the volume border") as e:
        gdm.extract_surface(ball[0], threshold=50, polarity="dark", seed=(3, 3, 3))
    assert "border" in e.value.reason
    assert e.value.result is not None and len(e.value.result.faces) > 0
    assert e.value.result.report["status"] == e.value.reason
    # the same run with the border allowed succeeds
    assert gdm.extract_surface(ball[0], threshold=50, polarity="dark", seed=(3, 3, 3), allow_border=True)


def test_time_limit_is_a_failure(ball):
    big, _ = sphere(60, radius=25.0)
    with pytest.raises(gdm.ModelFailed, match="ran out of time"):
        gdm.extract_surface(big, threshold=50, time_limit=1e-6, lod_face_area=1)


def test_files():
    with pytest.raises(FileNotFoundError):
        gdm.read_image("/nonexistent/scan.nii.gz")
    with pytest.raises(FileNotFoundError):
        gdm.read_mesh("/nonexistent/mesh.ply")


def test_corrupt_files(tmp_path):
    bad = tmp_path / "bad.mha"
    bad.write_text("ObjectType = Image\nNDims = 3\nDimSize = 10 10 10\nElementType = MET_SHORT\n"
                   "ElementDataFile = LOCAL\nshort")
    with pytest.raises(gdm.InvalidInput) as e:
        gdm.read_image(bad)
    assert isinstance(e.value, OSError) and "bad.mha" in str(e.value)
    mesh = tmp_path / "bad.ply"
    mesh.write_bytes(b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n1\n")
    with pytest.raises(gdm.InvalidInput):
        gdm.read_mesh(mesh)
    with pytest.raises(gdm.InvalidOption, match="unknown mesh extension"):
        gdm.read_mesh(bad)


def test_bad_progress(ball):
    with pytest.raises(TypeError, match="progress must be callable"):
        gdm.extract_surface(ball[0], threshold=50, progress=3)
