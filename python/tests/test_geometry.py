"""Axis order, physical space, layouts and dtypes."""
import numpy as np
import pytest

import gdm
from conftest import MRI_T1, PHANTOM, need, read_metaimage, sphere


def rotation(axis, degrees):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    a = np.radians(degrees)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(a) * k + (1 - np.cos(a)) * k @ k


def test_axis_order_is_itks(tmp_path):
    """read_image's array is ITK's buffer (x fastest) viewed as [i, j, k]: the
    MetaImage's bytes in Fortran order, and ITK's GetArrayFromImage ([k, j, i]) transposed."""
    array, spacing, origin, direction = gdm.read_image(PHANTOM)
    raw, raw_spacing, raw_origin = read_metaimage(PHANTOM)
    assert array.shape == (96, 96, 24) and array.dtype == np.float32
    assert array.flags.f_contiguous and not array.flags.owndata  # ITK's own buffer, no copy
    assert np.array_equal(array, raw.astype(np.float32))
    assert spacing == raw_spacing == (0.5, 0.5, 2.0) and origin == raw_origin
    itk_view = np.ascontiguousarray(array.T)  # what itk.GetArrayFromImage gives: [k, j, i], C order
    assert itk_view.shape == (24, 96, 96) and np.array_equal(itk_view.T, array)
    assert np.array_equal(direction, np.eye(3))


def test_axis_order_is_nibabels(tmp_path):
    """nibabel's get_fdata() is [i, j, k] too: a NIfTI written by nibabel reads
    back as the same array; its RAS affine is ITK's LPS geometry with x and y negated."""
    nib = pytest.importorskip("nibabel")
    values = np.arange(5 * 6 * 7, dtype=np.int16).reshape(5, 6, 7) * 3 - 40
    r = rotation((1, 2, 3), 30)
    spacing = np.array([0.8, 1.1, 2.5])
    affine = np.eye(4)
    affine[:3, :3] = r * spacing
    affine[:3, 3] = [-10.0, 4.0, 25.0]
    path = tmp_path / "small.nii.gz"
    nib.save(nib.Nifti1Image(values, affine), str(path))
    img = nib.load(str(path))
    array, sp, org, direction = gdm.read_image(path)
    assert np.array_equal(array, img.get_fdata())
    assert np.allclose(sp, img.header.get_zooms(), atol=1e-6)
    lps_to_ras = np.diag([-1.0, -1.0, 1.0])
    itk_affine = np.eye(4)
    itk_affine[:3, :3] = np.asarray(direction) * np.asarray(sp)
    itk_affine[:3, 3] = org
    assert np.allclose(np.diag([-1, -1, 1, 1]) @ itk_affine, img.affine, atol=1e-4)
    # from_affine: nibabel's geometry for extract_surface (the mesh is then in RAS)
    s2, o2, d2 = gdm.from_affine(img.affine)
    assert np.allclose(s2, sp, atol=1e-5) and np.allclose(o2, lps_to_ras @ np.asarray(org), atol=1e-4)
    assert np.allclose(d2, lps_to_ras @ direction, atol=1e-5)


def test_mri_t1_same_array_as_nibabel():
    need(MRI_T1, "the T1 MRI head (../shared/data/mri-head-t1/chris_t1.nii.gz)")
    nib = pytest.importorskip("nibabel")
    img = nib.load(str(MRI_T1))
    array, spacing, origin, direction = gdm.read_image(MRI_T1)
    data = img.get_fdata()
    assert array.shape == data.shape
    assert np.allclose(array, data, rtol=1e-6, atol=1e-3)
    itk_affine = np.eye(4)
    itk_affine[:3, :3] = np.asarray(direction) * np.asarray(spacing)
    itk_affine[:3, 3] = origin
    assert np.allclose(np.diag([-1, -1, 1, 1]) @ itk_affine, img.affine, atol=1e-3)


def check_ball(result, center, radius, voxel):
    distance = np.linalg.norm(result.vertices - center, axis=1)
    assert abs(distance.mean() - radius) < 0.15 * voxel, distance.mean()
    assert np.abs(distance - radius).max() < 0.6 * voxel
    m = result.report["mesh"]
    assert m["closed"] and m["manifold"] and m["genus"] == 0 and m["self_intersections"] == 0
    assert abs(m["volume_mm3"] / (4 / 3 * np.pi * radius**3) - 1) < 0.03
    # the solid's centroid (signed tetrahedra from the origin): the ball's centre
    a, b, c = (result.vertices[result.faces[:, k]] for k in range(3))
    tet = np.einsum("ij,ij->i", a, np.cross(b, c)) / 6.0
    centroid = ((a + b + c) * tet[:, None]).sum(axis=0) / (4.0 * tet.sum())
    assert np.allclose(centroid, center, atol=0.1 * voxel), (centroid, center)


@pytest.mark.parametrize("rotated", [False, True])
def test_anisotropic_rotated_ball_in_physical_space(rotated):
    """A ball of radius 9 mm off the volume's centre, sampled with spacing
    (0.7, 1.0, 1.6) mm, a rotated direction and an origin far from 0: the mesh
    is the ball in mm, where the direction puts it."""
    spacing = (0.7, 1.0, 1.6)
    direction = rotation((1, -2, 0.5), 35) if rotated else np.eye(3)
    origin = (-20.0, 5.0, 30.0)
    dims = (50, 36, 24)
    center_index = np.array([26.0, 17.5, 12.0])
    center = np.asarray(origin) + direction @ (np.asarray(spacing) * center_index)
    volume, _ = sphere(dims, radius=9.0, spacing=spacing, origin=origin, direction=direction, center=center)
    result = gdm.extract_surface(volume, spacing, origin, direction, threshold=50)
    check_ball(result, center, 9.0, voxel=0.7)
    assert result.report["input"]["spacing_mm"] == list(spacing)


def test_direction_is_column_per_axis():
    """Column k of direction is axis k: a swap of two columns with the array's
    axes swapped is the same physical object and the same mesh."""
    spacing = (0.8, 1.0, 1.3)
    volume, center = sphere((30, 26, 22), radius=7.0, spacing=spacing)
    a = gdm.extract_surface(volume, spacing, (0, 0, 0), np.eye(3), threshold=50, seed=tuple(center))
    swapped = np.asfortranarray(volume.transpose(1, 0, 2))
    direction = np.eye(3)[:, [1, 0, 2]]  # axis 0 of the new array runs along y
    b = gdm.extract_surface(swapped, (1.0, 0.8, 1.3), (0, 0, 0), direction, threshold=50, seed=tuple(center))
    check_ball(a, center, 7.0, 0.8)
    check_ball(b, center, 7.0, 0.8)
    assert abs(a.report["mesh"]["volume_mm3"] - b.report["mesh"]["volume_mm3"]) < 0.01 * a.report["mesh"]["volume_mm3"]


def test_layouts_and_dtypes_give_the_same_mesh():
    base, _ = sphere(28, radius=8.0)
    integer = np.asfortranarray(np.round(base).astype(np.int16))
    reference = gdm.extract_surface(integer.astype(np.float32), threshold=50)
    variants = {
        "int16 F": integer,
        "int16 C": np.ascontiguousarray(integer),
        "int32": integer.astype(np.int32),
        "int64 C": np.ascontiguousarray(integer, dtype=np.int64),
        "uint8": integer.astype(np.uint8),
        "uint16": integer.astype(np.uint16),
        "float64 F": integer.astype(np.float64, order="F"),
        "float16": integer.astype(np.float16),
        "longdouble": integer.astype(np.longdouble),
        "big-endian float32": integer.astype(">f4"),
        "strided view": np.asfortranarray(np.repeat(integer, 2, axis=0))[::2],
        "list": integer.tolist(),
    }
    for name, array in variants.items():
        r = gdm.extract_surface(array, threshold=50)
        assert np.array_equal(r.vertices, reference.vertices), name
        assert np.array_equal(r.faces, reference.faces), name
    assert gdm.extract_surface(integer > 50, threshold=0.5).report["mesh"]["closed"]  # bool


def test_generation_and_report():
    volume, center = sphere(30, radius=9.0)
    r = gdm.extract_surface(volume, threshold=50, lod_face_area=6, global_refinements=0)
    assert r.generation.dtype == np.int32 and r.generation.shape == (len(r.vertices),)
    assert r.generation.max() == r.report["mesh"]["max_generation"] > 0
    p = r.report["parameters"]
    assert p["lod_face_area"] == 6.0 and p["global_refinements"] == 0 and p["polarity"] == "bright"
    assert p["subvoxel_fit"] is True and p["seed"] == "auto" and p["threshold"] == 50
    assert set(o["name"] for o in gdm.options()) <= set(p)
    assert r.report["threshold"] == {"value": 50.0, "source": "given"}
    assert r.report["model"]["stop_reason"] == "converged"
    # A smooth sphere's model: no edge folds anywhere near a fin's 160 degrees.
    m = r.report["mesh"]
    assert 0.0 < m["max_fold_deg"] < 90.0 and m["folds"] == 0
    otsu = gdm.extract_surface(volume)
    assert otsu.report["threshold"]["source"] == "otsu"


def opened_bottle(n=40, inner=12.0, outer=14.0, opening=6.0):
    """A dark cavity inside a bright wall pierced along +x by a round opening,
    dark outside; the cavity's centre in voxels."""
    c = (n - 1) / 2.0
    i, j, k = np.meshgrid(*[np.arange(n, dtype=float) - c] * 3, indexing="ij")
    r = np.sqrt(i * i + j * j + k * k)
    shell = np.maximum(r - outer, inner - r)
    hole = np.maximum(np.hypot(j, k) - opening / 2.0, -i)
    wall = np.maximum(shell, -hole)
    return np.asfortranarray((50.0 + 150.0 * np.clip(0.5 - wall, 0.0, 1.0)).astype(np.float32)), c


def test_gap_bridges_the_opening_of_a_bottle():
    """The gap keyword (docs/options.md): without it the model leaks out of the
    opening (ModelFailed, the border); with a gap above the opening it is bridged
    and the report says what the gap closed."""
    volume, c = opened_bottle()
    with pytest.raises(gdm.ModelFailed, match="border"):
        gdm.extract_surface(volume, threshold=125, polarity="dark", seed=(c, c, c))
    result = gdm.extract_surface(volume, threshold=125, polarity="dark", seed=(c, c, c), gap=8.0)
    model = result.report["model"]
    assert model["gap_closed_voxels"] > 0 and model["bridge_vertices"] > 0 and model["border_vertices"] == 0
    distance = np.linalg.norm(np.asarray(result.vertices) - c, axis=1)
    assert distance.max() < 13.0  # the cap continues the cavity's wall (radius 12)


def test_a_hollow_shell_gives_its_outer_surface():
    """fill_cavities (on by default): a model grown in the wall of a hollow
    sphere is the outer sphere, and the report says what was filled; off, the
    model lines the cavity and the report names where it meets itself."""
    n, inner, outer = 40, 9.0, 14.0
    c = (n - 1) / 2.0
    i, j, k = np.meshgrid(*[np.arange(n, dtype=float) - c] * 3, indexing="ij")
    r = np.sqrt(i * i + j * j + k * k)
    wall = np.maximum(r - outer, inner - r)
    volume = np.asfortranarray((50.0 + 150.0 * np.clip(0.5 - wall, 0.0, 1.0)).astype(np.float32))
    seed = (c + 11.5, c, c)
    solid = gdm.extract_surface(volume, threshold=125, seed=seed, seed_radius=1.5)
    assert solid.report["model"]["cavities"] == 1
    assert solid.report["model"]["cavity_volume_mm3"] > 2500.0  # 4/3 pi 9^3 = 3,054
    assert solid.report["contacts"]["regions"] == 0
    assert np.linalg.norm(np.asarray(solid.vertices) - c, axis=1).min() > outer - 1.0
    lined = gdm.extract_surface(volume, threshold=125, seed=seed, seed_radius=1.5, fill_cavities=False)
    assert lined.report["model"]["cavities"] == 0
    assert np.linalg.norm(np.asarray(lined.vertices) - c, axis=1).min() < inner + 1.0


def test_a_torus_is_capped_across_its_hole():
    """cap_handles (on by default, with fill_cavities): a model grown in a
    torus's tube keeps genus 0 by a membrane across the hole at its narrowest
    place, and the report's filled_regions says where; off, the model goes
    round the tube and the report names where its fronts meet; with
    handle_repair="cut" the tube is parted instead."""
    nx, nz, big, small = 44, 22, 12.0, 5.0
    cx, cz = (nx - 1) / 2.0, (nz - 1) / 2.0
    i, j, k = np.meshgrid(np.arange(nx) - cx, np.arange(nx) - cx, np.arange(nz) - cz, indexing="ij")
    tube = np.hypot(np.hypot(i, j) - big, k) - small
    volume = np.asfortranarray((50.0 + 150.0 * np.clip(0.5 - tube, 0.0, 1.0)).astype(np.float32))
    seed = (cx, cx - big, cz)
    capped = gdm.extract_surface(volume, threshold=125, seed=seed, seed_radius=1.5)
    model = capped.report["model"]
    assert model["handles"] == 1 and model["cavities"] == 0
    [cap] = [r for r in model["filled_regions"] if r["kind"] == "handle"]
    assert np.linalg.norm(np.asarray(cap["centre_mm"]) - (cx, cx, cz)) < 1.5  # the hole's waist
    assert abs(cap["hole_width_mm"] - 2.0 * (big - small)) < 2.5
    assert capped.report["contacts"]["regions"] == 0
    assert capped.report["mesh"]["genus"] == 0
    kept = gdm.extract_surface(volume, threshold=125, seed=seed, seed_radius=1.5, cap_handles=False)
    assert kept.report["model"]["handles"] == 0
    assert kept.report["contacts"]["regions"] > 0
    # Where the fronts met round the tube: a seam across the object, the
    # regions across the object summed.
    contacts = kept.report["contacts"]
    seams = [r for r in contacts["list"] if r["across"] == "object"]
    assert seams and contacts["seam_faces"] == sum(r["faces"] for r in seams)
    assert abs(contacts["seam_area_mm2"] - sum(r["area_mm2"] for r in seams)) < 1e-9 * contacts["area_mm2"]
    assert 0.0 < contacts["seam_area_mm2"] <= contacts["area_mm2"]
    assert capped.report["contacts"]["seam_area_mm2"] == 0.0
    # handle_repair="cut": the tube is parted instead (the hole stays open):
    # one cut across the tube, as wide as the tube, genus 0, no contact, and
    # the model's volume the torus's (2 pi^2 R r^2) but the cut's (three
    # voxels of the tube: 4 %; measured 5.9 % less in all), not the torus's
    # and the hole's.
    cut = gdm.extract_surface(volume, threshold=125, seed=seed, seed_radius=1.5, handle_repair="cut")
    model = cut.report["model"]
    assert model["handle_repair"] == "cut" and model["handles"] == 1
    [part] = [r for r in model["filled_regions"] if r["kind"] == "cut"]
    assert abs(part["body_width_mm"] - 2.0 * small) < 1.5
    assert abs(np.hypot(part["centre_mm"][0] - cx, part["centre_mm"][1] - cx) - big) < 1.5  # in the tube
    assert cut.report["mesh"]["genus"] == 0 and cut.report["contacts"]["regions"] == 0
    torus_volume = 2.0 * np.pi ** 2 * big * small ** 2
    assert abs(cut.report["mesh"]["volume_mm3"] - torus_volume) < 0.08 * torus_volume
    assert capped.report["mesh"]["volume_mm3"] > 1.2 * torus_volume


def test_topology_exact_follows_the_torus_and_the_cavity():
    """topology="exact": a torus's cap becomes a tube through the hole (genus
    1), a hollow ball's cavity its own inward component (2 components); the
    report says so, and the genus and components agree with chi."""
    rng = np.random.default_rng(15)
    nx, nz, big, small = 44, 22, 12.0, 5.0
    cx, cz = (nx - 1) / 2.0, (nz - 1) / 2.0
    i, j, k = np.meshgrid(np.arange(nx) - cx, np.arange(nx) - cx, np.arange(nz) - cz, indexing="ij")
    tube = np.hypot(np.hypot(i, j) - big, k) - small
    torus = 50.0 + 150.0 * np.clip(0.5 - tube, 0.0, 1.0) + rng.normal(0.0, 7.5, tube.shape)
    torus = np.asfortranarray(torus.astype(np.float32))
    seed = (cx, cx - big, cz)
    exact = gdm.extract_surface(torus, threshold=125, seed=seed, seed_radius=1.5, topology="exact")
    mesh, model = exact.report["mesh"], exact.report["model"]
    assert model["topology"] == "exact" and model["handles"] == 1 and model["handles_opened"] == 1
    assert mesh["genus"] == 1 and mesh["components"] == 1 and mesh["euler_consistent"]
    assert mesh["euler_characteristic"] == 0 and mesh["self_intersections"] == 0 and mesh["closed"]
    solid = gdm.extract_surface(torus, threshold=125, seed=seed, seed_radius=1.5)
    assert solid.report["mesh"]["genus"] == 0 and solid.report["model"]["topology"] == "solid"

    n, inner, outer = 40, 11.0, 14.0
    c = (n - 1) / 2.0
    i, j, k = np.meshgrid(*(np.arange(n) - c,) * 3, indexing="ij")
    r = np.sqrt(i * i + j * j + k * k)
    shell = np.maximum(r - outer, inner - r)
    ball = 50.0 + 150.0 * np.clip(0.5 - shell, 0.0, 1.0) + rng.normal(0.0, 7.5, shell.shape)
    ball = np.asfortranarray(ball.astype(np.float32))
    hollow = gdm.extract_surface(ball, threshold=125, seed=(c + 12.5, c, c), seed_radius=1.2, topology="exact")
    assert hollow.report["model"]["cavity_components"] == 1
    assert hollow.report["mesh"]["components"] == 2 and hollow.report["mesh"]["genus"] == 0
    radii = np.linalg.norm(np.asarray(hollow.vertices) - c, axis=1)
    assert (np.abs(radii - inner) < 1.0).sum() > 100 and (np.abs(radii - outer) < 1.0).sum() > 100


def test_face_budget():
    """face_budget (the catalogue's keyword, the command's --faces): about
    that many faces (within 5 %), a valid surface, the report says what was
    asked and obtained; below 20 faces is refused, naming the option."""
    volume, _ = sphere(40, radius=12.0)
    r = gdm.extract_surface(volume, threshold=50, face_budget=400)
    assert abs(len(r.faces) - 400) <= 20
    mesh, model = r.report["mesh"], r.report["model"]
    assert mesh["closed"] and mesh["genus"] == 0 and mesh["self_intersections"] == 0
    assert model["face_budget"] == 400 and model["budget_faces"] == len(r.faces)
    assert model["budget_collapses"] > 0 and r.report["parameters"]["face_budget"] == 400
    with pytest.raises(gdm.InvalidOption, match="face_budget must be 0 \\(off\\) or in \\[20, 1e\\+09\\], got 10"):
        gdm.extract_surface(volume, threshold=50, face_budget=10)


def test_a_shell_started_from_its_voxels_has_no_seams():
    """voxel_seed: a shell 4 voxels thick over a dark layer round a core,
    reached from the core through one bridge (the volume's lower cut opens
    the dark layer to the outside). Grown from the core, the model meets
    itself on the shell's far side (seams); started from the object's voxels
    it does not, and the report says how the seed was made."""
    nx, nz = 72, 64
    c = np.array([(nx - 1) / 2.0, (nx - 1) / 2.0, (nz - 1) / 2.0 + 8.0])  # the volume cuts the layer above
    i, j, k = np.meshgrid(np.arange(nx, dtype=float), np.arange(nx, dtype=float), np.arange(nz, dtype=float),
                          indexing="ij")
    r = np.sqrt((i - c[0]) ** 2 + (j - c[1]) ** 2 + (k - c[2]) ** 2)
    shell = np.maximum(r - 28.0, 24.0 - r)
    core = r - 20.0
    t = np.clip((i - c[0] - 18.0) / 8.0, 0.0, 1.0)  # a bridge along +x from the core to the shell
    bridge = np.sqrt((i - c[0] - 18.0 - 8.0 * t) ** 2 + (j - c[1]) ** 2 + (k - c[2]) ** 2) - 3.0
    sdf = np.minimum(np.minimum(shell, core), bridge)
    volume = np.asfortranarray((50.0 + 150.0 * np.clip(0.5 - sdf, 0.0, 1.0)).astype(np.float32))
    seed = tuple(c)
    grown = gdm.extract_surface(volume, threshold=125, seed=seed, seed_radius=3.0)
    voxel = gdm.extract_surface(volume, threshold=125, seed=seed, seed_radius=3.0, voxel_seed=True)
    assert not grown.report["model"]["voxel_seed"]
    model = voxel.report["model"]
    assert model["voxel_seed"] and model["voxel_seed_voxels"] > 0
    assert model["voxel_seed_surface_faces"] > len(voxel.faces)
    assert model["stage_seconds"]["voxel_seed"] > 0.0
    assert grown.report["contacts"]["seam_area_mm2"] > 200.0
    assert voxel.report["contacts"]["seam_area_mm2"] < 0.05 * grown.report["contacts"]["seam_area_mm2"]
    # The grown model's seams cover over 1 % of its area: the report says a start
    # from the voxels is worth it; started so, it does not.
    assert grown.report["contacts"]["seam_area_mm2"] > 0.01 * grown.report["mesh"]["area_mm2"]
    assert grown.report["contacts"]["seams_worth_a_voxel_seed"] is True
    assert voxel.report["contacts"]["seams_worth_a_voxel_seed"] is False
    assert voxel.report["mesh"]["genus"] == 0 and voxel.report["mesh"]["closed"]
    assert voxel.report["mesh"]["self_intersections"] == 0
