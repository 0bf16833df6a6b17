"""Shared fixtures of gdm's Python tests.

Run from the repository root after the build:
    PYTHONPATH=build/python python3 -m pytest python/tests
GDM_CLI (the gdm command) and GDM_SHARED_DIR (../shared) default to the build
tree and the folder next to the repository.
"""
import os
import pathlib
import subprocess

import numpy as np
import pytest

SOURCE = pathlib.Path(os.environ.get("GDM_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
SHARED = pathlib.Path(os.environ.get("GDM_SHARED_DIR", SOURCE.parent / "shared"))
CLI = pathlib.Path(os.environ.get("GDM_CLI", SOURCE / "build" / "itk-module" / "apps" / "gdm"))
PHANTOM = SOURCE / "data" / "phantom.mha"
TOOTH = SHARED / "data" / "tooth" / "tooth.mhd"
MRI_T1 = SHARED / "data" / "mri-head-t1" / "chris_t1.nii.gz"


def need(path, what):
    if not path.exists():
        pytest.skip(f"{what} not found at {path} (the shared data folder ../shared is absent)")


@pytest.fixture
def cli():
    if not CLI.exists():
        pytest.skip(f"the gdm command is not built at {CLI} (build the target gdm, GDM_BUILD_ITK=ON)")

    def run(*args):
        p = subprocess.run([str(CLI), *map(str, args)], capture_output=True, text=True)
        assert p.returncode == 0, f"gdm {' '.join(map(str, args))} failed ({p.returncode}):\n{p.stdout}\n{p.stderr}"
        return p

    return run


def sphere(n=40, radius=12.0, spacing=(1.0, 1.0, 1.0), origin=(0.0, 0.0, 0.0), direction=None, center=None,
           dtype=np.float32):
    """A bright ball (value 100 inside, 0 outside, a linear ramp over a voxel
    across the surface) in physical space, as an [i, j, k] array."""
    direction = np.eye(3) if direction is None else np.asarray(direction, float)
    spacing = np.asarray(spacing, float)
    dims = (n, n, n) if np.isscalar(n) else tuple(n)
    idx = np.stack(np.meshgrid(*[np.arange(d) for d in dims], indexing="ij"), axis=-1).astype(float)
    points = np.asarray(origin, float) + (idx * spacing) @ direction.T
    if center is None:
        center = np.asarray(origin, float) + direction @ (spacing * (np.asarray(dims) - 1) / 2.0)
    distance = np.linalg.norm(points - np.asarray(center, float), axis=-1)
    values = np.clip(50.0 + 50.0 * (radius - distance), 0.0, 100.0)
    return np.asfortranarray(values.astype(dtype)), np.asarray(center, float)


def parse_obj(path):
    vertices, faces = [], []
    for line in pathlib.Path(path).read_text().splitlines():
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "v":
            vertices.append([float(x) for x in parts[1:4]])
        elif parts[0] == "f":
            faces.append([int(x.split("/")[0]) - 1 for x in parts[1:4]])
    return np.array(vertices, dtype=np.float64), np.array(faces, dtype=np.int64)


def read_metaimage(path):
    """A MetaImage (.mha/.mhd) read with numpy alone, as ITK lays it out: x fastest."""
    import zlib
    path = pathlib.Path(path)
    raw = path.read_bytes()
    header, offset = {}, 0
    for line in raw.split(b"\n"):
        offset += len(line) + 1
        key, _, value = line.decode("latin-1").partition("=")
        header[key.strip()] = value.strip()
        if key.strip() == "ElementDataFile":
            break
    dims = [int(x) for x in header["DimSize"].split()]
    dtype = {"MET_SHORT": "<i2", "MET_UCHAR": "u1", "MET_USHORT": "<u2", "MET_FLOAT": "<f4"}[header["ElementType"]]
    data = raw[offset:] if header["ElementDataFile"] == "LOCAL" else (path.parent / header["ElementDataFile"]).read_bytes()
    if header.get("CompressedData", "False") == "True":
        data = zlib.decompress(data)
    flat = np.frombuffer(data, dtype=dtype, count=int(np.prod(dims)))
    # x fastest = Fortran order over [i, j, k]
    array = flat.reshape(dims[::-1]).transpose(2, 1, 0)
    spacing = tuple(float(x) for x in header.get("ElementSpacing", "1 1 1").split())
    origin = tuple(float(x) for x in header.get("Offset", "0 0 0").split())
    return array, spacing, origin


def icosphere(center, radius, level=1):
    """A geodesic sphere (20 * 4**level faces, outward), as (vertices, faces)."""
    t = (1 + 5 ** 0.5) / 2
    v = [[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t], [0, -1, -t], [0, 1, -t],
         [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]]
    f = [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6],
         [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10],
         [8, 6, 7], [9, 8, 1]]
    v = [list(np.asarray(p) / np.linalg.norm(p)) for p in v]
    for _ in range(level):
        cache, nf = {}, []

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in cache:
                m = (np.asarray(v[a]) + np.asarray(v[b])) / 2
                v.append(list(m / np.linalg.norm(m)))
                cache[key] = len(v) - 1
            return cache[key]

        for a, b, c in f:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            nf += [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
        f = nf
    return np.asarray(center, float) + radius * np.asarray(v), np.asarray(f, dtype=np.int32)
