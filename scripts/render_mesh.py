#!/usr/bin/python3
"""A picture of a froth mesh: the cells on one side of a plane through the middle are removed,
so the cut shows the cells inside; coloured by cell kind or by a cell array; the title gives the
mesh, r, seed and cell count. A crack's faces (the mesh's unshared faces that have a twin at their
place: the crack's two sides) are drawn in red over the cut. Rendered offscreen by VTK (python3-vtk9); without a display run it
under xvfb-run, as `froth render` does.

Usage: render_mesh.py MESH.vtu OUT.png [COLOR [WIDTH HEIGHT]]   (COLOR: kind (default) or a cell array)"""
import os
import sys

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

# Kinds 4 and 5: the cells of an interface's or a crack's seeds (on its facets, on its curves).
KIND_NAMES = ["interior", "fringe", "edge", "vertex", "interface or crack", "its curves"]
KIND_COLOURS = [(0.85, 0.85, 0.80), (0.35, 0.60, 0.85), (0.90, 0.45, 0.25), (0.80, 0.20, 0.45), (0.95, 0.80, 0.20),
                (0.45, 0.75, 0.35)]


def field(grid, name):
    a = grid.GetFieldData().GetAbstractArray(name)
    if a is None or a.GetNumberOfTuples() < 1:
        return None
    return a.GetVariantValue(0).ToString() if isinstance(a, vtk.vtkStringArray) else a.GetTuple1(0)


def cut_away(grid):
    """The cells whose seed lies on the near side of the plane x = middle of the mesh's box."""
    centres = grid.GetCellData().GetArray("seed")
    if centres is None:
        f = vtk.vtkCellCenters()
        f.SetInputData(grid)
        f.Update()
        points = vtk_to_numpy(f.GetOutput().GetPoints().GetData())
    else:
        points = vtk_to_numpy(centres)
    lo, hi = grid.GetBounds()[0:2]
    keep = vtk.vtkIdList()
    for c, p in enumerate(points):
        if p[0] <= 0.5 * (lo + hi):
            keep.InsertNextId(c)
    extract = vtk.vtkExtractCells()
    extract.SetInputData(grid)
    extract.SetCellList(keep)
    surface = vtk.vtkDataSetSurfaceFilter()
    surface.SetInputConnection(extract.GetOutputPort())
    surface.Update()
    return surface.GetOutput(), keep.GetNumberOfIds()


def crack_faces(grid):
    """The crack's faces, once each, or None for a mesh without cracks: on a crack each face of
    one side has a face of the other at its place (froth welds the two alike), where a face of the
    outer surface has none."""
    names = grid.GetFieldData().GetAbstractArray("crack_names")
    if names is None or names.GetNumberOfValues() == 0:
        return None
    surface = vtk.vtkDataSetSurfaceFilter()
    surface.SetInputData(grid)
    surface.Update()
    # Each face's vertex mean (vtkCellCenters' parametric centre of a polygon depends on its
    # first vertex, which differs between the two sides).
    polys = surface.GetOutput().GetPolys()
    offsets, ids = vtk_to_numpy(polys.GetOffsetsArray()), vtk_to_numpy(polys.GetConnectivityArray())
    xyz = vtk_to_numpy(surface.GetOutput().GetPoints().GetData())[ids]
    points = np.add.reduceat(xyz, offsets[:-1], axis=0) / np.diff(offsets)[:, None]
    r = field(grid, "r") or 1.0
    keys = np.round(points / (1e-6 * r)).astype(np.int64)
    _, first, counts = np.unique(keys, axis=0, return_index=True, return_counts=True)
    twice = vtk.vtkIdList()
    for c in first[counts == 2]:
        twice.InsertNextId(int(c))
    extract = vtk.vtkExtractCells()
    extract.SetInputData(surface.GetOutput())
    extract.SetCellList(twice)
    faces = vtk.vtkGeometryFilter()
    faces.SetInputConnection(extract.GetOutputPort())
    faces.Update()
    return faces.GetOutput()


def main(mesh, out, colour="kind", width=1200, height=900):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(mesh)
    reader.Update()
    grid = reader.GetOutput()
    cells = grid.GetNumberOfCells()
    if cells == 0:
        sys.exit(f"{mesh}: no cells to draw")
    shown, kept = cut_away(grid)

    mapper = vtk.vtkPolyDataMapper()
    mapper.SetInputData(shown)
    if colour == "kind":
        table = vtk.vtkLookupTable()
        kinds = len(KIND_NAMES) if grid.GetCellData().GetArray("kind").GetRange()[1] >= 4 else 4
        table.SetNumberOfTableValues(kinds)
        for k, rgb in enumerate(KIND_COLOURS[:kinds]):
            table.SetTableValue(k, *rgb, 1.0)
            table.SetAnnotation(vtk.vtkVariant(k), KIND_NAMES[k])
        table.SetTableRange(0, kinds - 1)
        table.IndexedLookupOn()
        mapper.SetLookupTable(table)
        mapper.SetScalarModeToUseCellFieldData()
        mapper.SelectColorArray("kind")
        mapper.SetScalarRange(0, kinds - 1)
    else:
        if shown.GetCellData().GetArray(colour) is None:
            cd = shown.GetCellData()
            names = ", ".join(cd.GetArrayName(i) for i in range(cd.GetNumberOfArrays()))
            print(f"{mesh}: no cell array named {colour} (it has {names})", file=sys.stderr)
            sys.exit(2)  # the arguments are wrong: froth render exits 2 (usage)
        mapper.SetScalarModeToUseCellFieldData()
        mapper.SelectColorArray(colour)
        mapper.SetScalarRange(shown.GetCellData().GetArray(colour).GetRange(0))
    mapper.ScalarVisibilityOn()
    bar = vtk.vtkScalarBarActor()
    bar.SetLookupTable(mapper.GetLookupTable())
    bar.SetTitle(colour)
    bar.SetNumberOfLabels(4)
    bar.SetWidth(0.08)
    bar.SetHeight(0.5)
    bar.SetPosition(0.9, 0.25)
    for p in (bar.GetTitleTextProperty(), bar.GetLabelTextProperty()):
        p.SetColor(0, 0, 0)
        p.ShadowOff()

    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    prop = actor.GetProperty()
    prop.EdgeVisibilityOn()
    prop.SetEdgeColor(0.1, 0.1, 0.1)
    prop.SetLineWidth(1.0)

    renderer = vtk.vtkRenderer()
    renderer.SetBackground(1, 1, 1)
    renderer.AddActor(actor)
    renderer.AddActor2D(bar)
    crack = crack_faces(grid)
    if crack is not None and crack.GetNumberOfCells() > 0:
        crack_mapper = vtk.vtkPolyDataMapper()
        crack_mapper.SetInputData(crack)
        crack_mapper.ScalarVisibilityOff()
        crack_actor = vtk.vtkActor()
        crack_actor.SetMapper(crack_mapper)
        crack_actor.GetProperty().SetColor(0.85, 0.05, 0.05)
        crack_actor.GetProperty().SetOpacity(0.85)
        renderer.AddActor(crack_actor)
    r, seed = field(grid, "r"), field(grid, "random_seed")
    title = os.path.basename(mesh)
    if r is not None:
        title += f": r = {r:.4g}"
    if seed is not None:
        title += f", seed {int(seed)}"
    title += f", {cells} cells (cut at the middle: {kept} shown)"
    text = vtk.vtkTextActor()
    text.SetInput(title)
    text.GetTextProperty().SetFontSize(22)
    text.GetTextProperty().SetColor(0, 0, 0)
    text.SetPosition(15, height - 40)
    renderer.AddActor2D(text)

    # Looking at the cut face (the removed side is +x), a little from above and the side.
    camera = renderer.GetActiveCamera()
    camera.SetFocalPoint(0, 0, 0)
    camera.SetPosition(1.0, -0.55, 0.45)
    camera.SetViewUp(0, 0, 1)
    renderer.ResetCamera()
    camera.Zoom(1.15)

    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(width, height)
    window.AddRenderer(renderer)
    window.Render()
    image = vtk.vtkWindowToImageFilter()
    image.SetInput(window)
    image.Update()
    writer = vtk.vtkPNGWriter()
    writer.SetFileName(out)
    writer.SetInputConnection(image.GetOutputPort())
    writer.Write()


if __name__ == "__main__":
    if len(sys.argv) not in (3, 4, 6):
        sys.exit(__doc__)
    size = (int(sys.argv[4]), int(sys.argv[5])) if len(sys.argv) == 6 else (1200, 900)
    main(sys.argv[1], sys.argv[2], sys.argv[3] if len(sys.argv) >= 4 else "kind", *size)
