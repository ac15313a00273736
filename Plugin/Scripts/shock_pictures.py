"""Picture of a shock in an OpenFOAM solution: the Mach number on a cut
through the fitted shock surfaces, with the mesh's edges on the cut and the
surfaces' trace in white, zoomed on the middle of the surfaces, as the
paper's Fig. 10 (pvpython; needs an X
display: adapt_case.py runs it under xvfb-run when there is none).

    pvpython Plugin/Scripts/shock_pictures.py CASE TIME SURFACES.vtp OUT.png
            [--mach-range LO HI] [--title TEXT] [--zoom F] [--gas GAMMA R]

CASE          an OpenFOAM case (read with VTK's OpenFOAM reader), or a .vtu
              with point data U and T (then --gas GAMMA R is needed), or a
              .vtp cut already made (write_cut: point data Mach, the plane
              in field data CutOrigin and CutNormal; what adapt_case.py
              hands over, so that the child does not read the whole solution)
TIME          the time to show (a time directory's name; ignored for a .vtu
              or .vtp)
SURFACES.vtp  AdaptToShocks' fitted surfaces (its output port 1)
OUT.png       the picture (1200 x 900)

The cut: for a one-cell-deep case the mid-depth plane; otherwise the plane
through the surfaces' centre that holds the mean flow direction and the
surface normal there (cut_plane).  The view is F (default 0.35) of the surfaces' extent,
centred on the surface point nearest their centre.  Mach = |U| / sqrt(gamma R T), gamma and R from the case's
constant/thermophysicalProperties (hConst, perfectGas; U and T are in the
start fields too, rho is not).  The colour range is
LO..HI (default: the cut's range), so that pictures before and after share
one scale.
"""
import argparse
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def cut_plane(P, U, surf):
    """(S, centre, normal): the surfaces' points S (the grid's points P when
    there are none) and the cut's plane, from the grid's points P and point
    velocities U (numpy) and the fitted surfaces `surf` (vtkPolyData)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    S = vtk_to_numpy(surf.GetPoints().GetData()) if surf.GetNumberOfPoints() else P
    centre = 0.5 * (S.min(axis=0) + S.max(axis=0))
    depth = [k for k in range(3) if len(np.unique(P[:, k])) == 2]
    if depth:
        normal = np.eye(3)[depth[0]]
        centre[depth[0]] = 0.5 * (P[:, depth[0]].min() + P[:, depth[0]].max())
    else:
        flow = U.mean(axis=0)
        flow /= np.linalg.norm(flow)
        # the surface normal at the point nearest the centre
        from vtkmodules.vtkFiltersCore import vtkPolyDataNormals
        nf = vtkPolyDataNormals()
        nf.SetInputData(surf)
        nf.SplittingOff()
        nf.Update()
        N = vtk_to_numpy(nf.GetOutput().GetPointData().GetNormals())
        i = int(np.argmin(np.linalg.norm(S - centre, axis=1)))
        centre = S[i]
        normal = np.cross(flow, N[i])
        if np.linalg.norm(normal) < 1e-6:
            normal = np.cross(flow, [0.0, 0.0, 1.0])
        normal /= np.linalg.norm(normal)
    return S, centre, normal


def mach_cut(source, gamma_r, centre, normal):
    """The Mach number |U| / sqrt(gamma_r T) of `source` (a proxy with point
    data U and T) cut by the plane (centre, normal): a Calculator and a
    Slice proxy; returns (calculator, slice)."""
    from paraview.simple import Calculator, Slice
    mach = Calculator(Input=source, AttributeType="Point Data", ResultArrayName="Mach",
                      Function="mag(U)/sqrt(%.12g*T)" % gamma_r)
    cut = Slice(Input=mach)
    cut.Triangulatetheslice = 0  # the cells as they are (quads of hexahedra)
    cut.SliceType = "Plane"
    cut.SliceType.Origin = list(centre)
    cut.SliceType.Normal = list(normal)
    return mach, cut


def write_cut(grid, surfaces_vtp, gas, path):
    """The picture's cut of `grid` (a vtkUnstructuredGrid with point data U
    and T) made in this process and written to `path` (.vtp: point data U,
    T and Mach, the plane as field data CutOrigin and CutNormal), so that
    shock_pictures.py given `path` draws what it draws from the grid."""
    from paraview.simple import PVTrivialProducer, Delete
    from paraview import servermanager
    from vtkmodules.util.numpy_support import vtk_to_numpy, numpy_to_vtk
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader, vtkXMLPolyDataWriter
    # only U and T: the solution's other arrays would be cut too
    slim = grid.NewInstance()
    slim.ShallowCopy(grid)
    slim.GetCellData().Initialize()
    pd = slim.GetPointData()
    for name in [pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays())]:
        if name not in ("U", "T"):
            pd.RemoveArray(name)
    r = vtkXMLPolyDataReader()
    r.SetFileName(surfaces_vtp)
    r.Update()
    _, centre, normal = cut_plane(vtk_to_numpy(slim.GetPoints().GetData()),
                                  vtk_to_numpy(pd.GetArray("U")), r.GetOutput())
    source = PVTrivialProducer()
    source.GetClientSideObject().SetOutput(slim)
    mach, cut = mach_cut(source, gas[0] * gas[1], centre, normal)
    leaf = servermanager.Fetch(cut)
    while leaf.IsA("vtkMultiBlockDataSet"):
        leaf = leaf.GetBlock(0)
    # in their own types (float32 from float32 points or U): the view is
    # computed from them as the child computes it from a grid
    for name, value in (("CutOrigin", centre), ("CutNormal", normal)):
        a = numpy_to_vtk(np.ascontiguousarray(value).reshape(1, 3), deep=1)
        a.SetName(name)
        leaf.GetFieldData().AddArray(a)
    w = vtkXMLPolyDataWriter()
    w.SetInputData(leaf)
    w.SetFileName(path)
    w.SetDataModeToBinary()
    w.SetCompressorTypeToNone()
    w.Write()
    for p in (cut, mach, source):
        Delete(p)


def read_grid(a):
    """The volume with point data U and T of a case (at a.time) or a .vtu,
    and its gas (gamma, R)."""
    sys.path.insert(0, os.path.join(HERE, "..", "..", "Data"))
    import foam_case
    if a.case.endswith(".vtu"):
        # a grid adapt_case.py already holds (point data U and T), with its gas
        if a.gas is None:
            sys.exit("shock_pictures.py: a .vtu source needs --gas GAMMA R")
        from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
        vtu = vtkXMLUnstructuredGridReader()
        vtu.SetFileName(a.case)
        vtu.Update()
        return vtu.GetOutput(), tuple(a.gas)
    gas = a.gas if a.gas else foam_case.gas_properties(a.case)[:2]
    # VTK's reader, not the proxy: the proxy's SkipZeroTime takes effect
    # only after the time list was made, and a case written by
    # adapt_case.py has only its start time 0 until it is solved.
    from vtkmodules.vtkIOGeometry import vtkOpenFOAMReader
    foam = vtkOpenFOAMReader()
    foam.SetFileName(os.path.join(a.case, "shock_pictures.foam"))
    foam.SkipZeroTimeOff()
    foam.UpdateInformation()
    foam.DisableAllPatchArrays()
    foam.SetPatchArrayStatus("internalMesh", 1)
    foam.EnableAllCellArrays()
    foam.UpdateTimeStep(float(a.time))
    grid = foam.GetOutput()
    while grid is not None and grid.IsA("vtkMultiBlockDataSet"):
        grid = grid.GetBlock(0)
    return grid, tuple(gas)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("case")
    ap.add_argument("time")
    ap.add_argument("surfaces")
    ap.add_argument("out")
    ap.add_argument("--mach-range", nargs=2, type=float)
    ap.add_argument("--title", default="")
    ap.add_argument("--gas", nargs=2, type=float, metavar=("GAMMA", "R"),
                    help="the gas (default: the case's constant/thermophysicalProperties)")
    ap.add_argument("--zoom", type=float, default=0.35,
                    help="the view's size as a fraction of the surfaces' extent (default 0.35)")
    a = ap.parse_args()
    from paraview.simple import (PVTrivialProducer, XMLPolyDataReader, Slice, CreateView, Show,
                                 ColorBy, GetColorTransferFunction, GetScalarBar, Text, SaveScreenshot)
    from paraview import servermanager
    from vtkmodules.util.numpy_support import vtk_to_numpy

    surf_reader = XMLPolyDataReader(FileName=[a.surfaces])
    surf = servermanager.Fetch(surf_reader)
    if a.case.endswith(".vtp"):
        # a cut write_cut made (adapt_case.py): the plane is in its field data
        from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
        r = vtkXMLPolyDataReader()
        r.SetFileName(a.case)
        r.Update()
        made = r.GetOutput()
        fd = made.GetFieldData()
        if (made.GetPointData().GetArray("Mach") is None or fd.GetArray("CutOrigin") is None
                or fd.GetArray("CutNormal") is None):
            sys.exit("shock_pictures.py: %s is not a cut (point data Mach, field data CutOrigin and CutNormal)"
                     % a.case)
        centre, normal = (vtk_to_numpy(fd.GetArray(n))[0].copy() for n in ("CutOrigin", "CutNormal"))
        # no surfaces: the cut's points stand for the grid's
        S = (vtk_to_numpy(surf.GetPoints().GetData()) if surf.GetNumberOfPoints() else
             vtk_to_numpy(made.GetPoints().GetData()))
        cut = PVTrivialProducer()
        cut.GetClientSideObject().SetOutput(made)
    else:
        grid, gas = read_grid(a)
        if grid is None or grid.GetPointData().GetArray("U") is None or grid.GetPointData().GetArray("T") is None:
            sys.exit("shock_pictures.py: %s at time %s has no volume with U and T point data" % (a.case, a.time))
        reader = PVTrivialProducer()
        reader.GetClientSideObject().SetOutput(grid)
        S, centre, normal = cut_plane(vtk_to_numpy(grid.GetPoints().GetData()),
                                      vtk_to_numpy(grid.GetPointData().GetArray("U")), surf)
        _, cut = mach_cut(reader, gas[0] * gas[1], centre, normal)
    trace = Slice(Input=surf_reader)
    trace.SliceType = "Plane"
    trace.SliceType.Origin = list(centre)
    trace.SliceType.Normal = list(normal)
    view = CreateView("RenderView")
    view.ViewSize = [1200, 900]
    view.OrientationAxesVisibility = 0
    view.Background = [1.0, 1.0, 1.0]
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    d = Show(cut, view)
    d.SetRepresentationType("Surface With Edges")
    d.EdgeColor = [0.35, 0.35, 0.35]
    ColorBy(d, ("POINTS", "Mach"))
    lut = GetColorTransferFunction("Mach")
    lut.ApplyPreset("Jet", True)
    if a.mach_range:
        lut.RescaleTransferFunction(*a.mach_range)
    else:
        leaf = servermanager.Fetch(cut)
        while leaf.IsA("vtkMultiBlockDataSet"):
            leaf = leaf.GetBlock(0)
        lut.RescaleTransferFunction(*leaf.GetPointData().GetArray("Mach").GetRange())
    bar = GetScalarBar(lut, view)
    bar.Title = "Mach"
    bar.ComponentTitle = ""
    bar.TitleColor = bar.LabelColor = [0, 0, 0]
    d.SetScalarBarVisibility(view, True)
    t = Show(trace, view)
    t.DiffuseColor = t.AmbientColor = [1.0, 1.0, 1.0]
    t.LineWidth = 3.0
    if a.title:
        label = Text(Text=a.title)
        ld = Show(label, view)
        ld.Color = [1, 1, 1]
        ld.Shadow = 1
        ld.FontSize = 14
        ld.WindowLocation = "Upper Center"
    # camera: look along the cut's normal at the surfaces' extent on it
    up = np.cross(normal, [1.0, 0.0, 0.0])
    if np.linalg.norm(up) < 1e-6:
        up = np.cross(normal, [0.0, 1.0, 0.0])
    up /= np.linalg.norm(up)
    right = np.cross(up, normal)
    ext_r = np.ptp((S - centre) @ right)
    ext_u = np.ptp((S - centre) @ up)
    # centred on the surface point nearest the surfaces' centre (on the cut)
    on_cut = S[np.abs((S - centre) @ normal) <= 0.05 * max(ext_r, ext_u, 1e-12)]
    base = on_cut if len(on_cut) else S
    mid = base[np.argmin(np.linalg.norm(base - 0.5 * (base.min(axis=0) + base.max(axis=0)), axis=1))].copy()
    mid -= ((mid - centre) @ normal) * normal
    view.CameraFocalPoint = list(mid)
    view.CameraPosition = list(mid + normal * max(ext_r, ext_u, 1e-6) * 4)
    view.CameraViewUp = list(up)
    view.CameraParallelProjection = 1
    view.CameraParallelScale = 0.6 * a.zoom * max(ext_u, ext_r * 900.0 / 1200.0, 1e-6)
    SaveScreenshot(a.out, view, ImageResolution=[1200, 900])
    print("shock_pictures.py: %s" % a.out)


if __name__ == "__main__":
    main()
