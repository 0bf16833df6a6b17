"""No memory growth over repeated calls; mesh files; wrap."""
import gc
import json
import os
import resource
import tracemalloc

import numpy as np
import pytest

import gdm
from conftest import icosphere, sphere


# meshio 7.0 (Debian 12) reads VTK unstructured grids only, not the legacy POLYDATA gdm writes.
MESHIO_READS = (".ply", ".obj", ".stl", ".off")


def rss_bytes():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def test_no_memory_growth_over_50_calls(tmp_path):
    volume, _ = sphere(40, radius=14.0)
    calls = lambda: gdm.extract_surface(volume, threshold=50)  # noqa: E731
    for _ in range(5):  # warm up: allocator pools, numpy caches
        calls()
    gc.collect()
    rss0, peak0 = rss_bytes(), resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    tracemalloc.start()
    traced0 = tracemalloc.get_traced_memory()[0]
    faces = None
    for _ in range(50):
        r = calls()
        faces = len(r.faces) if faces is None else faces
        assert len(r.faces) == faces
        del r
    gc.collect()
    traced1, traced_peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    rss1, peak1 = rss_bytes(), resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    figures = {"calls": 50, "faces": faces, "volume_MB": volume.nbytes / 2**20,
               "rss_before_MB": rss0 / 2**20, "rss_after_MB": rss1 / 2**20, "rss_growth_kB": (rss1 - rss0) / 1024,
               "maxrss_growth_kB": (peak1 - peak0) / 1024, "tracemalloc_growth_B": traced1 - traced0,
               "tracemalloc_peak_kB": traced_peak / 1024}
    print("\nmemory over 50 calls: " + json.dumps(figures))
    out = os.environ.get("GDM_MEMORY_REPORT")
    if out:
        with open(out, "w") as f:
            json.dump(figures, f, indent=1)
    assert traced1 - traced0 < 64 * 1024  # Python objects (numpy arrays are traced): nothing kept
    assert rss1 - rss0 < 4 * 2**20        # the process: no growth beyond allocator noise


@pytest.mark.parametrize("ext", [".ply", ".obj", ".stl", ".off", ".vtk"])
def test_write_mesh_formats_read_back(tmp_path, ext):
    volume, _ = sphere(24, radius=7.0)
    r = gdm.extract_surface(volume, threshold=50)
    path = tmp_path / ("ball" + ext)
    gdm.write_mesh(path, r)
    back = gdm.read_mesh(path)
    assert back.faces.shape == r.faces.shape
    exact = ext in (".obj", ".off", ".vtk")  # 17 digits or doubles; .ply and .stl are float
    if exact:
        assert np.array_equal(back.vertices, r.vertices)
    elif ext == ".ply":
        assert np.allclose(back.vertices, r.vertices, atol=1e-5)
    else:  # STL: corners per face, welded on reading in another order
        key = lambda v: v[np.lexsort(v.T[::-1])]  # noqa: E731
        assert np.allclose(key(back.vertices), key(r.vertices.astype(np.float32).astype(float)), atol=1e-6)
    if ext in (".ply", ".vtk"):
        assert np.array_equal(back.generation, r.generation)
    assert not [p for p in os.listdir(tmp_path) if ".tmp" in p]
    meshio = pytest.importorskip("meshio")
    if ext in MESHIO_READS:
        m = meshio.read(str(path))
        assert m.cells_dict["triangle"].shape == r.faces.shape
        if ext != ".stl":  # STL stores corners per face: compare the faces count only
            assert np.allclose(m.points, r.vertices, atol=1e-5)


def test_write_mesh_is_atomic_and_checked(tmp_path):
    volume, _ = sphere(24, radius=7.0)
    r = gdm.extract_surface(volume, threshold=50)
    with pytest.raises(OSError):
        gdm.write_mesh(tmp_path / "missing" / "ball.ply", r)
    assert not (tmp_path / "missing").exists()
    with pytest.raises(gdm.InvalidOption, match="unknown mesh extension"):
        gdm.write_mesh(tmp_path / "ball.xyz", r)
    with pytest.raises(gdm.InvalidOption, match="refers to vertex"):
        gdm.write_mesh(tmp_path / "bad.off", (r.vertices, r.faces + len(r.vertices)))
    gdm.write_mesh(str(tmp_path / "tuple.off"), (r.vertices, r.faces))
    assert (tmp_path / "tuple.off").exists() and os.listdir(tmp_path) == ["tuple.off"]


def test_wrap_a_soup_with_a_hole():
    vertices, faces = icosphere((5, -3, 2), 10.0, 2)
    open_faces = faces[5:]  # a hole
    r = gdm.wrap(vertices, open_faces, tolerance=1.5)
    m = r.report["mesh"]
    assert m["closed"] and m["manifold"] and m["genus"] == 0 and m["self_intersections"] == 0
    assert r.report["farthest_input_distance_mm"] <= 1.5
    capped = gdm.wrap(vertices, open_faces, tolerance=1.5, bridge=12)  # the hole capped smoothly
    m = capped.report["mesh"]
    assert m["closed"] and m["manifold"] and m["genus"] == 0 and m["self_intersections"] == 0
    with pytest.raises(gdm.InvalidOption, match="tolerance"):
        gdm.wrap(vertices, faces, tolerance=0)
    with pytest.raises(gdm.InvalidOption, match="cell_size"):
        gdm.wrap(vertices, faces, tolerance=1, cell_size=2)


def test_wrap_too_costly_is_refused_with_the_estimate():
    vertices, faces = icosphere((5, -3, 2), 10.0, 2)
    e = gdm.estimate_wrap(vertices, faces, tolerance=1.5)
    assert e["cells"] == e["grid"][0] * e["grid"][1] * e["grid"][2] and e["faces"] > 0 and e["bytes"] > 0
    with pytest.raises(gdm.WrapTooCostly, match="the wrap would take about .* refused before starting") as info:
        gdm.wrap(vertices, faces, tolerance=0.003, cell_size=0.001)  # 1e13 cells: refused before any work
    assert isinstance(info.value, gdm.InvalidOption) and info.value.option == "cell_size"
    assert info.value.estimate["bytes"] > 2 * 2**30 and info.value.fitting_cell_size > 0.001
    with pytest.raises(gdm.WrapTooCostly, match="memory limit of 0.001 GiB"):
        gdm.wrap(vertices, faces, tolerance=1.5, memory_limit=0.001, time_limit=0)
    with pytest.raises(gdm.InvalidOption, match="time_limit"):
        gdm.wrap(vertices, faces, tolerance=1.5, time_limit=-1)
