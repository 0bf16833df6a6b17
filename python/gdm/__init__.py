"""gdm: closed, simple triangle meshes of objects in 3D volumes (Geometrically
Deformed Models, Miller et al., SIGGRAPH 1991), from numpy arrays.

    import gdm
    volume, spacing, origin, direction = gdm.read_image("scan.nii.gz")
    result = gdm.extract_surface(volume, spacing, origin, direction, threshold=400)
    result.vertices, result.faces          # (N, 3) float64 mm, (M, 3) int32
    gdm.write_mesh("scan.ply", result)

The computation is gdm's C++ pipeline (gdm::prepare_model + gdm::run_model),
the code path of the `gdm` command: the same volume and options give the same
mesh, bit for bit.

Axis order: a volume is indexed [i, j, k] with i along the image's x axis
(ITK's index order; nibabel's get_fdata() order). Voxel (i, j, k) lies at
origin + direction @ (spacing * (i, j, k)) in mm; direction's column k is the
direction of axis k (ITK's GetDirection()). A Fortran-ordered float32 array is
ITK's memory layout and is copied with one memcpy into the core's buffer; any
other layout or real dtype is converted in the same single pass (no temporary
numpy copy). gdm.read_image returns ITK's buffer itself (no copy).

Every option of the catalogue (gdm.options(); docs/options.md) is a keyword
of extract_surface with the catalogue's name and default.
"""
import inspect as _inspect
import os as _os
import errno as _errno
from dataclasses import dataclass as _dataclass, field as _field

import numpy as _np

from . import _gdm
from ._gdm import (Error, InvalidOption, InvalidVolume, InvalidSeed, InvalidInput, ModelFailed, Cancelled,
                   WrapTooCostly)

__version__ = _gdm.__version__
__all__ = ["extract_surface", "read_image", "write_mesh", "read_mesh", "wrap", "estimate_wrap", "options", "from_affine",
           "Result", "Error", "InvalidOption", "InvalidVolume", "InvalidSeed", "InvalidInput", "ModelFailed",
           "Cancelled", "WrapTooCostly"]


@_dataclass(eq=False)
class Result:
    """A mesh from gdm: vertices (N x 3 float64, mm), faces (M x 3 int32,
    counter-clockwise seen from outside), generation (N int32: the
    deformation cycle that created each vertex) and report (a dict: the
    gdm command's JSON report without the file names)."""
    vertices: _np.ndarray
    faces: _np.ndarray
    generation: _np.ndarray
    report: dict = _field(default_factory=dict)

    def __repr__(self):
        m = self.report.get("mesh", {})
        text = f"gdm.Result({len(self.vertices)} vertices, {len(self.faces)} faces"
        if m:
            text += (f", closed={m.get('closed')}, genus={m.get('genus')}, "
                     f"volume={m.get('volume_mm3', 0.0):.6g} mm^3")
        return text + ")"


def _result(raw):
    return Result(raw["vertices"], raw["faces"], raw["generation"], raw["report"])


def _finish(raw):
    result = _result(raw)
    if raw["cancelled"]:
        e = Cancelled("cancelled by the progress callback")
        e.result = result
        raise e
    if raw["failure"]:
        e = ModelFailed(raw["failure"])
        e.reason = raw["failure"]
        e.result = result
        raise e
    return result


def options():
    """The catalogue of options: a list of dicts (name, group, unit, help,
    type, default, range, choices, alias), in the catalogue's order."""
    return _gdm.option_catalogue()


def extract_surface(volume, spacing=(1.0, 1.0, 1.0), origin=(0.0, 0.0, 0.0), direction=None, threshold=None,
                    seed="auto", progress=None, *, seed_index=None, roi=None, **options):
    """The closed mesh of the object in `volume` (see the module's help for
    the axis order).

    volume     3D array [i, j, k], any real dtype, C or Fortran order
    spacing    (sx, sy, sz) mm; origin (x, y, z) mm; direction 3x3 (column k = axis k) or None
    threshold  None or "otsu" (Otsu's method), or T in image units
    polarity   "bright" (object above T, the default) or "dark"
    seed       "auto" (the deepest point of the largest object region), a point
               (x, y, z) in mm, or a closed mesh (vertices, faces)
    seed_index (i, j, k): the seed at that voxel's centre
    roi        (i0, j0, k0, i1, j1, k1): crop to this inclusive voxel box first
    progress   progress(cycle, faces, moving) is called after every deformation
               cycle; returning False cancels (gdm.Cancelled). Ctrl-C cancels too.
    **options  every option of gdm.options(), by its name (a0=1, lod_face_area=10, ...)

    Returns a gdm.Result. Raises InvalidOption (a bad value, ValueError;
    .option names it), TypeError (an unknown keyword), InvalidVolume,
    InvalidSeed (ValueError), ModelFailed (the model leaked to the border,
    hit a limit; .reason, .result), Cancelled.
    """
    return _finish(_gdm.extract_surface(volume, spacing, origin, direction, threshold, seed, seed_index, roi,
                                        progress, **options))


def _signature():
    # The keywords shown by help() and inspect: the fixed ones, then the
    # catalogue's (read from the C++ catalogue, never listed here).
    params = list(_inspect.signature(extract_surface).parameters.values())[:-1]
    names = {p.name for p in params}
    for o in _gdm.option_catalogue():
        if o["name"] not in names:
            params.append(_inspect.Parameter(o["name"], _inspect.Parameter.KEYWORD_ONLY, default=o["default"]))
    return _inspect.Signature(params)


extract_surface.__signature__ = _signature()
extract_surface.__doc__ += "\n    Options (name = default: help [unit; range]):\n" + "".join(
    f"      {o['name']} = {o['default']!r}: {o['help']} [{(o['unit'] + '; ') if o['unit'] else ''}{o['range']}]\n"
    for o in _gdm.option_catalogue())


def read_image(path, series=None):
    """Reads a volume through gdm's reader (the gdm command's): a DICOM series
    folder (the series with most slices, or `series`: a UID or a prefix), a
    DICOM file, .mha/.mhd, .nrrd/.nhdr, .nii/.nii.gz, .vtk; any scalar type,
    as float32 (DICOM rescale applied).

    Returns (array, spacing, origin, direction): array float32 [i, j, k] in
    Fortran order (ITK's buffer itself, no copy), spacing and origin tuples
    in mm, direction a 3x3 array (column k = axis k), in ITK's LPS world
    (nibabel's affine is RAS: see gdm.from_affine). Raises FileNotFoundError,
    InvalidInput (an OSError: unreadable, truncated, corrupt), InvalidVolume,
    InvalidOption (no such series)."""
    if not _gdm.has_image_io:
        raise NotImplementedError("gdm was built without ITK (GDM_BUILD_ITK=OFF): read_image is not available")
    path = _os.fspath(path)
    if not _os.path.exists(path):
        raise FileNotFoundError(_errno.ENOENT, _os.strerror(_errno.ENOENT), path)
    array, spacing, origin, direction, _info = _gdm.read_image(path, series)
    return array, spacing, origin, direction


def _mesh_parts(mesh):
    if isinstance(mesh, Result) or (hasattr(mesh, "vertices") and hasattr(mesh, "faces")):
        return mesh.vertices, mesh.faces, getattr(mesh, "generation", None)
    if isinstance(mesh, (tuple, list)) and len(mesh) in (2, 3):
        return mesh[0], mesh[1], (mesh[2] if len(mesh) == 3 else None)
    raise TypeError(f"mesh must be a gdm.Result or (vertices, faces[, generation]), got {type(mesh).__name__}")


def write_mesh(path, mesh):
    """Writes `mesh` (a gdm.Result or (vertices, faces[, generation])) by the
    extension of `path`, the gdm command's formats: .ply (binary, float, with
    the per-vertex generation), .obj, .stl (binary), .off, .vtk (double
    points, generation as point data); through a temporary name renamed to
    `path`, so a failed write leaves no partial file. Raises InvalidOption
    (unknown extension, bad arrays) or OSError."""
    vertices, faces, generation = _mesh_parts(mesh)
    _gdm.write_mesh(_os.fspath(path), vertices, faces, generation)


def read_mesh(path):
    """Reads .ply, .obj, .off, .stl, .vtk into a gdm.Result (generation when
    the file has it, else zeros; an empty report). Raises InvalidInput."""
    path = _os.fspath(path)
    if not _os.path.exists(path):
        raise FileNotFoundError(_errno.ENOENT, _os.strerror(_errno.ENOENT), path)
    raw = _gdm.read_mesh(path)
    generation = raw["generation"]
    if generation is None:
        generation = _np.zeros(len(raw["vertices"]), dtype=_np.int32)
    return Result(raw["vertices"], raw["faces"], generation, {})


def wrap(vertices, faces, tolerance, cell_size=None, *, coverage_rounds=4, a0=1.0, a1=1.0, a2=5.0,
         lod_face_area=10.0, global_refinements=0, max_cycles=2000, threads=0, time_limit=180.0,
         memory_limit=2.0, bridge=0.0, progress=None):
    """Shrink-wraps a triangle soup (holes, several pieces, noise):
    a closed, genus-0, self-intersection-free mesh around it, at most
    `tolerance` mm from the input (gdm::shrink_wrap, the `gdm wrap` command).
    cell_size: the distance field's cell, mm (default tolerance / 3).
    time_limit (s), memory_limit (GiB): a wrap whose estimate (estimate_wrap)
    exceeds either is refused at once with gdm.WrapTooCostly (an
    InvalidOption); 0 = no limit.
    bridge (mm; 0 = off; e.g. 10 x tolerance): openings up
    to about this wide with no input under them (holes) get a smooth cap (the
    envelope of balls of that diameter) instead of the wrap sinking in.
    Returns a gdm.Result; report has farthest_input_distance_mm and friends."""
    return _finish(_gdm.wrap(vertices, faces, float(tolerance), cell_size, int(coverage_rounds), float(a0),
                             float(a1), float(a2), float(lod_face_area), int(global_refinements), int(max_cycles),
                             int(threads), float(time_limit), float(memory_limit), float(bridge), progress))


def estimate_wrap(vertices, faces, tolerance, cell_size=None, *, coverage_rounds=4, a0=1.0, a1=1.0, a2=5.0,
                  lod_face_area=10.0, global_refinements=0, max_cycles=2000, threads=0, time_limit=180.0,
                  memory_limit=2.0, bridge=0.0):
    """What gdm.wrap with the same arguments would cost, estimated in
    milliseconds without wrapping: a dict with grid (cells per axis), cells,
    area_mm2, faces, cycles, seconds, bytes (peak memory) and text."""
    return _gdm.estimate_wrap(vertices, faces, float(tolerance), cell_size, int(coverage_rounds), float(a0),
                              float(a1), float(a2), float(lod_face_area), int(global_refinements), int(max_cycles),
                              int(threads), float(time_limit), float(memory_limit), float(bridge))


def from_affine(affine):
    """(spacing, origin, direction) of a 4x4 voxel-to-world affine (e.g.
    nibabel's img.affine, which maps to RAS+). The mesh of extract_surface is
    then in that affine's world. gdm.read_image and ITK give LPS+: the same
    point has x and y negated (affine = diag(-1, -1, 1, 1) @ ITK's)."""
    a = _np.asarray(affine, dtype=float)
    if a.shape != (4, 4):
        raise InvalidVolume(f"affine must be 4x4, got shape {a.shape}")
    m = a[:3, :3]
    spacing = _np.linalg.norm(m, axis=0)
    if not _np.all(spacing > 0):
        raise InvalidVolume(f"affine has a zero column: {a.tolist()}")
    return tuple(spacing.tolist()), tuple(a[:3, 3].tolist()), m / spacing
