#!/usr/bin/env python3
"""Renders a gdm mesh to a PNG with VTK, off screen.

    render_mesh.py MESH PICTURE.png [--title TEXT] [--size 480] [--display auto|xvfb|display]

--colour generation (default): by vertex generation, the deformation cycle
that created each vertex (the .ply's `generation` property, the .vtk's point
data; files without it are coloured by height); curvature: by mean
curvature; height: by z. Debian's VTK 9.1 (python3-vtk9) renders through X only (no
OSMesa or EGL window in its build), so without a usable $DISPLAY (or with
--display xvfb) this script starts its own Xvfb server for the picture:
`Xvfb -displayfd` picks a free display itself, so parallel jobs do not race
for one (as `xvfb-run -a` can).
"""

import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np

PLY_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2",
             "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
             "float": "f4", "float32": "f4", "double": "f8", "float64": "f8"}


def read_ply(path):
    """(points N x 3, triangles M x 3, generation N or None) of a binary or ASCII PLY."""
    with open(path, "rb") as f:
        header = []
        while True:
            line = f.readline()
            if not line:
                raise ValueError("%s: no end_header" % path)
            line = line.decode("ascii", "replace").strip()
            header.append(line)
            if line == "end_header":
                break
        body = f.read()
    fmt = next(l.split()[1] for l in header if l.startswith("format"))
    endian = "<" if fmt == "binary_little_endian" else ">"
    elements = []  # [name, count, [(prop, type) | (prop, "list", count type, item type)]]
    for l in header:
        w = l.split()
        if w[0] == "element":
            elements.append([w[1], int(w[2]), []])
        elif w[0] == "property":
            elements[-1][2].append((w[-1], "list", w[2], w[3]) if w[1] == "list" else (w[2], w[1]))
    data = {}
    if fmt == "ascii":
        tokens = body.split()
        pos = 0
        for name, count, props in elements:
            rows = []
            for _ in range(count):
                row = []
                for p in props:
                    if p[1] == "list":
                        n = int(tokens[pos]); pos += 1
                        row.append([float(t) for t in tokens[pos:pos + n]]); pos += n
                    else:
                        row.append(float(tokens[pos])); pos += 1
                rows.append(row)
            data[name] = (props, rows)
        verts = data["vertex"]
        names = [p[0] for p in verts[0]]
        pts = np.array([[r[names.index(c)] for c in "xyz"] for r in verts[1]])
        gen = np.array([r[names.index("generation")] for r in verts[1]]) if "generation" in names else None
        tris = np.array([r[0] for r in data["face"][1]], dtype=np.int64)
        return pts, tris, gen
    pos = 0
    for name, count, props in elements:
        if all(p[1] != "list" for p in props):
            dtype = np.dtype([(p[0], endian + PLY_TYPES[p[1]]) for p in props])
            arr = np.frombuffer(body, dtype=dtype, count=count, offset=pos)
            pos += dtype.itemsize * count
            data[name] = arr
        elif len(props) == 1:  # faces: a list per face; gdm writes triangles only
            _, _, ctype, itype = props[0]
            cdt, idt = np.dtype(endian + PLY_TYPES[ctype]), np.dtype(endian + PLY_TYPES[itype])
            first = int(np.frombuffer(body, cdt, 1, pos)[0]) if count else 3
            if count and first == 3:
                dtype = np.dtype([("n", cdt), ("v", idt, (3,))])
                arr = np.frombuffer(body, dtype=dtype, count=count, offset=pos)
                if np.all(arr["n"] == 3):
                    data[name] = arr["v"].astype(np.int64)
                    pos += dtype.itemsize * count
                    continue
            faces = []
            for _ in range(count):  # general polygons: fan-triangulate
                n = int(np.frombuffer(body, cdt, 1, pos)[0]); pos += cdt.itemsize
                idx = np.frombuffer(body, idt, n, pos); pos += idt.itemsize * n
                faces += [[idx[0], idx[i], idx[i + 1]] for i in range(1, n - 1)]
            data[name] = np.array(faces, dtype=np.int64).reshape(-1, 3)
        else:
            raise ValueError("%s: element %s mixes lists and scalars" % (path, name))
    v = data["vertex"]
    pts = np.stack([v["x"], v["y"], v["z"]], axis=1).astype(np.float64)
    gen = v["generation"].astype(np.float64) if "generation" in v.dtype.names else None
    return pts, data["face"], gen


def polydata(path):
    """A vtkPolyData and the name of the array to colour by (or None)."""
    import vtk
    from vtk.util import numpy_support as ns
    lower = path.lower()
    if lower.endswith(".ply"):
        pts, tris, gen = read_ply(path)
        poly = vtk.vtkPolyData()
        points = vtk.vtkPoints()
        points.SetData(ns.numpy_to_vtk(np.ascontiguousarray(pts), deep=True))
        poly.SetPoints(points)
        cells = np.hstack([np.full((len(tris), 1), 3, np.int64), tris]).ravel()
        ca = vtk.vtkCellArray()
        ca.SetCells(len(tris), ns.numpy_to_vtkIdTypeArray(cells, deep=True))
        poly.SetPolys(ca)
        if gen is not None:
            arr = ns.numpy_to_vtk(gen, deep=True)
            arr.SetName("generation")
            poly.GetPointData().AddArray(arr)
            return poly, "generation"
        return poly, None
    if lower.endswith(".off"):
        with open(path) as f:
            words = [w for l in f for w in l.split("#")[0].split()]
        if words[0] != "OFF":
            raise ValueError("%s: not an OFF file" % path)
        nv, nf = int(words[1]), int(words[2])
        pts = np.array(words[4:4 + 3 * nv], float).reshape(nv, 3)
        tris, pos = [], 4 + 3 * nv
        for _ in range(nf):
            n = int(words[pos]); idx = [int(w) for w in words[pos + 1:pos + 1 + n]]; pos += 1 + n
            tris += [[idx[0], idx[i], idx[i + 1]] for i in range(1, n - 1)]
        poly = vtk.vtkPolyData()
        points = vtk.vtkPoints()
        points.SetData(ns.numpy_to_vtk(pts, deep=True))
        poly.SetPoints(points)
        tris = np.array(tris, np.int64)
        cells = np.hstack([np.full((len(tris), 1), 3, np.int64), tris]).ravel()
        ca = vtk.vtkCellArray()
        ca.SetCells(len(tris), ns.numpy_to_vtkIdTypeArray(cells, deep=True))
        poly.SetPolys(ca)
        return poly, None
    reader = {".vtk": vtk.vtkPolyDataReader, ".stl": vtk.vtkSTLReader, ".obj": vtk.vtkOBJReader}[
        os.path.splitext(lower)[1]]()
    reader.SetFileName(path)
    if lower.endswith(".vtk"):
        reader.ReadAllScalarsOn()
    reader.Update()
    poly = reader.GetOutput()
    if poly.GetPointData().GetArray("generation") is not None:
        return poly, "generation"
    return poly, None


def render(mesh, picture, title, size, colour):
    import vtk
    from vtk.util import numpy_support as ns
    poly, scalars = polydata(mesh)
    if poly.GetNumberOfPolys() == 0:
        raise ValueError("%s: no faces" % mesh)
    normals = vtk.vtkPolyDataNormals()
    normals.SetInputData(poly)
    normals.SplittingOff()
    normals.ConsistencyOn()
    normals.Update()
    surface = normals.GetOutput()
    if colour == "generation" and scalars is None:
        colour = "height"  # no generation in this file (.stl, .obj, .off)
    if colour == "curvature":
        curv = vtk.vtkCurvatures()
        curv.SetCurvatureTypeToMean()
        curv.SetInputData(surface)
        curv.Update()
        surface = curv.GetOutput()
        values = ns.vtk_to_numpy(surface.GetPointData().GetArray("Mean_Curvature"))
        lo, hi = (float(v) for v in np.percentile(values, [5, 95]))
        surface.GetPointData().SetActiveScalars("Mean_Curvature")
        label = "curvature 1/mm"
    elif colour == "height":
        elev = vtk.vtkElevationFilter()
        b = surface.GetBounds()
        elev.SetLowPoint(0, 0, b[4])
        elev.SetHighPoint(0, 0, b[5])
        elev.SetScalarRange(b[4], b[5])
        elev.SetInputData(surface)
        elev.Update()
        surface = elev.GetOutput()
        label, lo, hi = "z (mm)", b[4], b[5]
        surface.GetPointData().SetActiveScalars("Elevation")
    else:
        surface.GetPointData().SetActiveScalars(scalars)
        lo, hi = surface.GetPointData().GetArray(scalars).GetRange()
        label = "generation"
    if hi <= lo:
        hi = lo + 1
    lut = vtk.vtkLookupTable()
    lut.SetHueRange(0.667, 0.0)  # blue (early) to red (late)
    lut.SetSaturationRange(0.75, 0.75)
    lut.SetValueRange(0.95, 0.95)
    lut.SetTableRange(lo, hi)
    lut.Build()
    mapper = vtk.vtkPolyDataMapper()
    mapper.SetInputData(surface)
    mapper.SetLookupTable(lut)
    mapper.SetScalarRange(lo, hi)
    mapper.SetScalarModeToUsePointData()
    mapper.ScalarVisibilityOn()
    mapper.InterpolateScalarsBeforeMappingOn()
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetInterpolationToGouraud()
    actor.GetProperty().SetSpecular(0.2)
    actor.GetProperty().SetSpecularPower(20)

    renderer = vtk.vtkRenderer()
    renderer.AddActor(actor)
    renderer.SetBackground(1.0, 1.0, 1.0)
    renderer.SetBackground2(0.78, 0.82, 0.88)
    renderer.GradientBackgroundOn()
    bar = vtk.vtkScalarBarActor()
    bar.SetLookupTable(lut)
    bar.SetTitle(label)
    bar.SetNumberOfLabels(3)
    bar.UnconstrainedFontSizeOn()
    bar.SetWidth(0.17)
    bar.SetHeight(0.45)
    bar.SetPosition(0.80, 0.08)
    for tp in (bar.GetTitleTextProperty(), bar.GetLabelTextProperty()):
        tp.SetColor(0.1, 0.1, 0.1)
        tp.SetFontSize(11)
        tp.ItalicOff()
        tp.ShadowOff()
    renderer.AddActor2D(bar)
    if title:
        text = vtk.vtkTextActor()
        text.SetInput(title)
        text.GetTextProperty().SetColor(0.1, 0.1, 0.1)
        text.GetTextProperty().SetFontSize(14)
        text.SetDisplayPosition(8, size - 22)
        renderer.AddActor2D(text)

    camera = renderer.GetActiveCamera()
    renderer.ResetCamera()
    camera.Azimuth(35)
    camera.Elevation(25)
    camera.OrthogonalizeViewUp()
    renderer.ResetCamera()
    camera.Zoom(0.95)

    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(size, size)
    window.AddRenderer(renderer)
    window.Render()
    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.ReadFrontBufferOff()
    grab.Update()
    writer = vtk.vtkPNGWriter()
    tmp = picture + ".tmp.png"
    writer.SetFileName(tmp)
    writer.SetInputConnection(grab.GetOutputPort())
    writer.Write()
    window.Finalize()
    os.replace(tmp, picture)


def display_usable():
    if not os.environ.get("DISPLAY"):
        return False
    try:
        return subprocess.run(["xdpyinfo"], capture_output=True, timeout=10).returncode == 0
    except (OSError, subprocess.TimeoutExpired):
        return True  # no xdpyinfo to ask: trust $DISPLAY


def main():
    ap = argparse.ArgumentParser(description="Renders a gdm mesh to a PNG with VTK, off screen.")
    ap.add_argument("mesh")
    ap.add_argument("picture")
    ap.add_argument("--title", default="")
    ap.add_argument("--size", type=int, default=480)
    ap.add_argument("--display", default="auto", choices=("auto", "xvfb", "display"))
    ap.add_argument("--colour", default="generation", choices=("generation", "curvature", "height"))
    a = ap.parse_args()
    if a.display == "display" or (a.display == "auto" and display_usable()):
        render(a.mesh, a.picture, a.title, a.size, a.colour)
        return 0
    # Our own X server: Xvfb writes the display number it took to a pipe.
    read_fd, write_fd = os.pipe()
    errors = tempfile.TemporaryFile()  # a file, not a pipe: Xvfb never blocks on it
    try:
        xvfb = subprocess.Popen(["Xvfb", "-displayfd", str(write_fd), "-screen", "0", "1024x768x24",
                                 "-nolisten", "tcp", "-noreset"], pass_fds=(write_fd,),
                                stdout=subprocess.DEVNULL, stderr=errors)
    except FileNotFoundError:
        print("render_mesh: no usable $DISPLAY and no Xvfb to render in (Debian: apt-get install xvfb)",
              file=sys.stderr)
        os.close(read_fd)
        os.close(write_fd)
        return 3
    os.close(write_fd)
    try:
        with os.fdopen(read_fd) as f:
            number = f.readline().strip()
        if not number:
            xvfb.wait(timeout=10)
            errors.seek(0)
            raise RuntimeError("Xvfb did not start: %s" % errors.read().decode(errors="replace")[-300:])
        os.environ["DISPLAY"] = ":" + number  # read when VTK opens its window
        render(a.mesh, a.picture, a.title, a.size, a.colour)
        return 0
    finally:
        xvfb.terminate()
        try:
            xvfb.wait(timeout=10)
        except subprocess.TimeoutExpired:
            xvfb.kill()


if __name__ == "__main__":
    sys.exit(main())
