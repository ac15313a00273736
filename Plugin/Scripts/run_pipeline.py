"""The adaptation pipeline on the bundled data, as far as it exists (pvbatch).

    pvbatch Plugin/Scripts/run_pipeline.py --plugin <AdaptiveRedistribution.so> \
        --data Data --output AdaptiveRedistribution-output [--input SOLUTION ...]

With --input (any file ParaView reads: .vtu, .foam, .cgns, .vtk, ...), each
solution is adapted in one step by AdaptToShocks with its defaults instead:
<output>/<name>_adapted.vtu (the adapted mesh), <name>_shock_surfaces.vtp
(the fitted surfaces, SurfaceId), <name>_adapted.png (a cut through the
adapted mesh, the new cells coloured), and a summary row each.

Without --input, the bundled data, step by step:

Stage 1 (paper section 2.2), the sensors, and stage 2 (section 2.3), the
feature clusters, their medial points and the fitted, trimmed shock surfaces:
- Data/wedge15Ma5.vtu, OpenFOAM rhoCentralFoam's Mach 5 flow over a 15 degree
  wedge (hexahedra): ShockSensor (NormalMach, ShockCells) and WeightFunction
  on the conserved variables; the shock angle fitted to the shock cells is
  compared with the theta-beta-Mach relation; the mesh adapted to the fitted
  shock plane by EmbeddedRemesh's 2-D mode (wedge15Ma5_adapted.vtu).
- Data/oblique_shock_unstructured.vtu, an analytic 3-D oblique shock on a Gmsh
  tetrahedral mesh: the same, compared with the exact shock plane.
- Data/cone20Ma2p5.vtu (when present), OpenFOAM on a Gmsh mesh around a 20
  degree cone at Mach 2.5: the conical shock fitted as a cone, compared with
  Taylor-Maccoll; the mesh adapted to the fitted cone by EmbeddedRemesh
  (cone20Ma2p5_adapted.vtu/.msh), and again with prism layers on both sides
  of it (LayerType Prisms: cone20Ma2p5_adapted_prisms.vtu/.msh, cuts through
  the layers cone20Ma2p5_cut_prisms*.png, the dihedral angles of every kind
  of cell cone20Ma2p5_dihedral_histogram_prisms.png).

Writes <output>/*_sensors.vtu (the meshes with the sensor and cluster
arrays, for ParaView), *_medial.vtp (the medial points), PNG pictures, and
*_shock_surface.vtp (the fitted surfaces), and prints a summary table.
"""
import argparse
import os
import sys

import numpy as np
from paraview.simple import *
from paraview import servermanager

parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
parser.add_argument("--plugin", required=True, help="the built AdaptiveRedistribution.so")
parser.add_argument("--data", required=True, help="the repository's Data/ folder")
parser.add_argument("--output", required=True, help="folder for the meshes and pictures")
parser.add_argument("--input", nargs="+", help="solutions to adapt with AdaptToShocks's defaults (one step each)")
args = parser.parse_args()

LoadPlugin(args.plugin, remote=False, ns=globals())
sys.path.insert(0, args.data)
from theta_beta_mach import shock_angle  # noqa: E402

os.makedirs(args.output, exist_ok=True)
summary = []


def print_summary(header, summary, output):
    """The run's table (rows: name, count, result) and the files written."""
    print()
    print(header)
    print("|---|---|---|")
    for row in summary:
        print("| %s | %d | %s |" % row)
    print()
    print("Wrote to %s:" % output)
    for f in sorted(os.listdir(output)):
        print("  " + f)


def region_colouring(annotations, colours):
    """A display set-up: edges, cells coloured by the categories of Region
    (annotations: value, label, ...; colours: r g b per category)."""
    def setup(display, view):
        display.Representation = "Surface With Edges"
        display.EdgeColor = [0.1, 0.1, 0.2]
        ColorBy(display, ("CELLS", "Region"))
        lut = GetColorTransferFunction("Region")
        lut.InterpretValuesAsCategories = 1
        lut.Annotations = annotations
        lut.IndexedColors = colours
        display.SetScalarBarVisibility(view, True)
        bar = GetScalarBar(lut, view)
        bar.Title = "Region"
        bar.TitleColor = [0, 0, 0]
        bar.LabelColor = [0, 0, 0]
    return setup


def adapt_inputs(paths):
    """AdaptToShocks with its defaults on each solution: the adapted mesh, the
    surfaces, a cut picture, a summary row; exit 1 if one failed."""
    failed = 0
    for path in paths:
        name = os.path.splitext(os.path.basename(path))[0]
        solution = OpenDataFile(path)
        if solution is None:
            print("%s: ParaView has no reader for this file" % path)
            failed += 1
            continue
        if "MeshRegions" in solution.ListProperties():  # OpenFOAM: the internal mesh and the patches
            solution.MeshRegions = ["internalMesh"] + [n for n in solution.MeshRegions.Available if n.startswith("patch/")]
        if "CellArrays" in solution.ListProperties():
            solution.CellArrays = solution.CellArrays.Available
        if hasattr(solution, "TimestepValues") and solution.TimestepValues:
            times = solution.TimestepValues
            solution.UpdatePipeline(times[-1] if isinstance(times, (list, tuple)) else times)
        adapted = AdaptToShocks(Input=solution)
        adapted.UpdatePipeline()
        out = servermanager.Fetch(adapted)
        volume = out.GetBlock(0) if out.IsA("vtkMultiBlockDataSet") else out
        if volume is None or volume.GetCellData().GetArray("Region") is None:
            print("%s: AdaptToShocks did not adapt it (its message above says why)" % path)
            failed += 1
            continue
        fd = volume.GetFieldData()
        value = lambda n: fd.GetArray(n).GetValue(0)
        templates = fd.GetAbstractArray("SurfaceTemplates")
        save(adapted, name + "_adapted.vtu" if not out.IsA("vtkMultiBlockDataSet") else name + "_adapted.vtm")
        save(OutputPort(adapted, 1), name + "_shock_surfaces.vtp")
        b = volume.GetBounds()
        cut = Slice(Input=adapted)
        cut.SliceType.Origin = [0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5])]
        cut.SliceType.Normal = [0, 0, 1]

        cut.Crinkleslice = 1  # whole cells: the new ones show their size
        cut.UpdatePipeline()

        regions = region_colouring(["0", "kept cells", "1", "new cells", "2", "layer cells"],
                                   [0.85, 0.85, 0.85, 0.55, 0.75, 1.0, 1.0, 0.6, 0.3])

        def flat(view):
            view.ResetCamera()
            view.CameraPosition = [view.CameraFocalPoint[0], view.CameraFocalPoint[1], view.CameraFocalPoint[2] + 5 * (b[1] - b[0] + b[3] - b[2])]
            view.CameraViewUp = [0, 1, 0]
            view.ResetCamera()

        picture(name + "_adapted.png", [(cut, regions)], flat,
                "%s adapted by AdaptToShocks: %d -> %d nodes, %d surface(s) (%s); cut through the middle"
                % (name, value("InputNodes"), value("OutputNodes"), value("NumberOfSurfaces"),
                   ", ".join(templates.GetValue(i) for i in range(templates.GetNumberOfValues()))))
        summary.append(("%s AdaptToShocks: %d -> %d nodes" % (name, value("InputNodes"), value("OutputNodes")),
                        int(value("SurfaceTriangles")) if fd.GetArray("SurfaceTriangles") else int(value("SurfaceQuads")),
                        "surfaces %s; new cells at the shock %.2f of the input's size; smallest new angle %.1f deg; %.1f s"
                        % (", ".join(templates.GetValue(i) for i in range(templates.GetNumberOfValues())),
                           value("SurfaceSizeRatio"), value("MinDihedralAngleNew") if value("TwoDimensional") == 0
                           else value("MinTriangleAngleNew"),
                           sum(value(n) for n in ("SecondsSensor", "SecondsClusters", "SecondsFit", "SecondsRemesh")))))
    print_summary("| solution | surface triangles | result |", summary, args.output)
    sys.exit(1 if failed else 0)


def local(proxy):
    proxy.UpdatePipeline()
    from vtkmodules.numpy_interface import dataset_adapter as dsa
    return dsa.WrapDataObject(servermanager.Fetch(proxy))


def local_port(proxy, port):
    proxy.UpdatePipeline()
    from vtkmodules.numpy_interface import dataset_adapter as dsa
    return dsa.WrapDataObject(servermanager.Fetch(proxy, idx=port))


def centroids(grid):
    from vtkmodules.util.numpy_support import vtk_to_numpy
    cells = grid.VTKObject.GetCells()
    offsets = vtk_to_numpy(cells.GetOffsetsArray())
    conn = vtk_to_numpy(cells.GetConnectivityArray())
    pts = np.asarray(grid.Points)
    counts = np.diff(offsets)
    sums = np.add.reduceat(pts[conn], offsets[:-1], axis=0)
    return sums / counts[:, None]


def save(proxy, name):
    path = os.path.join(args.output, name)
    SaveData(path, proxy=proxy, DataMode="Binary", CompressorType="ZLib")
    return path


def picture(name, shows, camera, title):
    view = CreateView("RenderView")
    view.ViewSize = [1400, 900]
    view.OrientationAxesVisibility = 1
    view.Background = [1, 1, 1]
    view.UseColorPaletteForBackground = 0
    for source, setup in shows:
        display = Show(source, view)
        setup(display, view)
    text = Text(Text=title)
    td = Show(text, view)
    td.Color = [0, 0, 0]
    td.FontSize = 14
    td.WindowLocation = "Upper Center"
    td.ShowBorder = "Always"  # a white box behind the title, over a zoomed-in mesh
    td.BackgroundColor = [1, 1, 1, 0.85]
    td.BorderColor = [1, 1, 1]
    camera(view)
    path = os.path.join(args.output, name)
    SaveScreenshot(path, view, ImageResolution=[1400, 900])
    Delete(view)
    return path


def colored(array, association, lo, hi, preset, bar_title):
    def setup(display, view):
        ColorBy(display, (association, array))
        lut = GetColorTransferFunction(array)
        lut.ApplyPreset(preset, True)
        lut.RescaleTransferFunction(lo, hi)
        display.SetScalarBarVisibility(view, True)
        bar = GetScalarBar(lut, view)
        bar.Title = bar_title
        bar.ComponentTitle = ""
        bar.TitleColor = [0, 0, 0]
        bar.LabelColor = [0, 0, 0]
    return setup


def shock_edges(display, view):
    display.Representation = "Wireframe"
    display.AmbientColor = [0, 0, 0]
    display.DiffuseColor = [0, 0, 0]
    display.LineWidth = 1.5
    ColorBy(display, None)


if args.input:
    adapt_inputs(args.input)


# ---------------------------------------------------------------- the wedge
wedge = XMLUnstructuredGridReader(FileName=[os.path.join(args.data, "wedge15Ma5.vtu")])
src = local(wedge)
gamma = float(np.asarray(src.FieldData["Gamma"])[0])
mach = float(np.asarray(src.FieldData["UpstreamMach"])[0])
theta = float(np.asarray(src.FieldData["WedgeAngle"])[0])
sensor = ShockSensor(Input=wedge, VariableSet=2, Density=["POINTS", "rho"], Momentum=["POINTS", "rhoU"],
                     TotalEnergy=["POINTS", "rhoE"], Gamma=gamma)
weight = WeightFunction(Input=sensor, Variables=["rho", "rhoU", "rhoE"], ComputePointWeight=1)
out = local(weight)

shock = np.asarray(out.CellData["ShockCells"]) == 1
c = centroids(out)
region = shock & (c[:, 0] > 0.03) & (c[:, 0] < 0.28)
xy = c[region][:, :2]
xy0 = xy.mean(axis=0)
_, _, vt = np.linalg.svd(xy - xy0)
direction = vt[0] if vt[0][0] > 0 else -vt[0]
fitted = np.degrees(np.arctan2(direction[1], direction[0]))
exact = shock_angle(mach, theta, gamma)
summary.append(("wedge15Ma5 (OpenFOAM, %d hexahedra)" % out.GetNumberOfCells(), int(shock.sum()),
                "shock angle %.2f deg (theta-beta-Mach %.2f deg)" % (fitted, exact)))

clusters = FeatureCluster(Input=weight, SensorArray=["POINTS", "WeightFunction"], SensorRange=[1.5, 2.0],
                          DilationRings=1)
medial = local_port(clusters, 1)
SaveData(os.path.join(args.output, "wedge15Ma5_medial.vtp"), proxy=OutputPort(clusters, 1),
         DataMode="Binary", CompressorType="ZLib")
mp = np.asarray(medial.Points)
beyond = mp[:, 0] > 0.08  # the captured shock forms over the first cells behind the tip
_, _, vt = np.linalg.svd(mp[beyond, :2] - mp[beyond, :2].mean(axis=0))
direction = vt[0] if vt[0][0] > 0 else -vt[0]
medial_angle = np.degrees(np.arctan2(direction[1], direction[0]))
summary.append(("wedge15Ma5 medial points of W in [1.5, 2]", int(medial.GetNumberOfPoints()),
                "%d cluster(s); line through medial points beyond x = 0.08: %.2f deg"
                % (len(np.asarray(medial.FieldData["ClusterSizes"])), medial_angle)))

surface = QuadricFit(Input=OutputPort(clusters, 1), Domain=wedge, Template="Plane", ClusterId=0)
plane = local(surface)
normal = np.asarray(plane.FieldData["Normal"])
plane_angle = np.degrees(np.arctan2(abs(normal[0]), abs(normal[1])))
save(surface, "wedge15Ma5_shock_surface.vtp")
summary.append(("wedge15Ma5 QuadricFit plane (robust)", int(plane.GetNumberOfCells()),
                "shock plane %.2f deg (theta-beta-Mach %.2f deg)" % (plane_angle, exact)))

# The discrete surface-based path: the medial sheet of the W = 1.5 isosurface,
# with the wedge's front and back planes as symmetry planes (one cell deep).
zlo, zhi = src.VTKObject.GetBounds()[4:6]
w_iso = Contour(Input=weight, ContourBy=["POINTS", "WeightFunction"], Isosurfaces=[1.5], ComputeNormals=1)
w_sheet = MedialAxisDelaunay(Input=w_iso, Domain=wedge, SymmetryPlanes=[0, 0, zlo, 0, 0, 1, 0, 0, zhi, 0, 0, 1])
sheet = local(w_sheet)
save(w_sheet, "wedge15Ma5_medial_sheet.vtp")
wedge_cell = np.median(np.sqrt(np.asarray(local(CellSize(Input=wedge, ComputeVolume=1)).CellData["Volume"]) / (zhi - zlo)))
d_sheet = np.abs((np.asarray(sheet.Points) - np.asarray(plane.FieldData["Origin"])) @ normal) / wedge_cell
summary.append(("wedge15Ma5 MedialAxisDelaunay sheet of W = 1.5 (symmetry planes z = %.3f, %.3f)" % (zlo, zhi),
                int(sheet.GetNumberOfCells()),
                "%d sheet(s); distance to the QuadricFit plane max %.2f, mean %.2f cells"
                % (len(np.asarray(sheet.FieldData["SheetAreas"])), d_sheet.max(), d_sheet.mean())))

shocks = Threshold(Input=weight, Scalars=["CELLS", "ShockCells"], LowerThreshold=0.5, UpperThreshold=1.5)
top_view = lambda view: (view.ResetCamera(), setattr(view, "CameraPosition", [0.08, 0.076, 1.0]),
                         setattr(view, "CameraFocalPoint", [0.08, 0.076, 0.0]), setattr(view, "CameraViewUp", [0, 1, 0]),
                         setattr(view, "CameraParallelProjection", 1), setattr(view, "CameraParallelScale", 0.095))
save(clusters, "wedge15Ma5_sensors.vtu")
picture("wedge15Ma5_NormalMach.png",
        [(weight, colored("NormalMach", "POINTS", 0.0, 2.0, "Cool to Warm", "Normal Mach")),
         (shocks, shock_edges)], top_view,
        "Mach 5, 15 deg wedge (OpenFOAM): normal Mach number; shock cells outlined (fitted %.2f deg, theory %.2f deg)"
        % (fitted, exact))


def medial_dots(display, view):
    display.Representation = "Points"
    display.PointSize = 6
    display.RenderPointsAsSpheres = 1
    display.ColorArrayName = ["POINTS", ""]
    display.AmbientColor = [0.1, 0.9, 0.3]
    display.DiffuseColor = [0.1, 0.9, 0.3]


def surface_edges(display, view):
    display.Representation = "Surface With Edges"
    display.ColorArrayName = ["POINTS", ""]
    display.DiffuseColor = [0.3, 0.6, 1.0]
    display.EdgeColor = [0.0, 0.0, 0.4]


picture("wedge15Ma5_WeightFunction.png",
        [(weight, colored("WeightFunction", "CELLS", 1.0, 2.0, "Inferno (matplotlib)", "W")),
         (OutputPort(clusters, 1), medial_dots)], top_view,
        "Weight function W (Soni et al.) on the conserved variables; medial points of W in [1.5, 2] in green")
def translucent_pressure(display, view):
    colored("p", "POINTS", 1.0, 5.0, "Viridis (matplotlib)", "p")(display, view)
    display.Opacity = 0.45


def red_lines(display, view):
    display.Representation = "Wireframe"
    display.ColorArrayName = ["POINTS", ""]
    display.AmbientColor = [0.9, 0.1, 0.1]
    display.DiffuseColor = [0.9, 0.1, 0.1]
    display.LineWidth = 3.0


picture("wedge15Ma5_shock_surface.png",
        [(weight, translucent_pressure), (surface, red_lines)], top_view,
        "Fitted shock plane, edge-on in red (QuadricFit, %.2f deg; theta-beta-Mach %.2f deg), over the pressure"
        % (plane_angle, exact))

# ---- EmbeddedRemesh in 2-D mode: the wedge is one cell deep, so the
# cross-section is remeshed around the fitted shock line and extruded into
# wedges (every cell still spans the depth, as an OpenFOAM 2-D case needs).
adapted_w = EmbeddedRemesh(Input=wedge, Surfaces=[surface], Mode="LocalCavity")
aw = local(adapted_w)
save(adapted_w, "wedge15Ma5_adapted.vtu")
fw = lambda n: float(np.asarray(aw.FieldData[n])[0])
summary.append(("wedge15Ma5 EmbeddedRemesh (2-D mode) on the fitted plane: %d -> %d nodes (%d removed, %d new), "
                "%d -> %d cells" % (fw("InputNodes"), fw("OutputNodes"), fw("RemovedNodes"), fw("NewNodes"),
                                    src.GetNumberOfCells(), aw.GetNumberOfCells()),
                int(fw("SurfaceQuads")),
                "%d kept hexahedra + %d new wedges; new triangles' min / mean angle %.1f / %.1f deg; volume change %.1e"
                % (fw("KeptCells"), fw("NewCells"), fw("MinTriangleAngleNew"), fw("MeanDihedralAngleNew"),
                   fw("RelativeVolumeChange"))))


region_edges = region_colouring(["0", "kept hexahedra", "1", "new wedges"], [0.85, 0.85, 0.85, 0.55, 0.75, 1.0])


shock_view = lambda view: (view.ResetCamera(), setattr(view, "CameraPosition", [0.15, 0.07, 1.0]),
                           setattr(view, "CameraFocalPoint", [0.15, 0.07, 0.0]), setattr(view, "CameraViewUp", [0, 1, 0]),
                           setattr(view, "CameraParallelProjection", 1), setattr(view, "CameraParallelScale", 0.1))
picture("wedge15Ma5_adapted_mesh.png",
        [(adapted_w, region_edges), (OutputPort(adapted_w, 1), red_lines)], shock_view,
        "Wedge adapted in 2-D mode (EmbeddedRemesh): %d -> %d nodes; the fitted shock (red) is a layer of faces"
        % (fw("InputNodes"), fw("OutputNodes")))

# ------------------------------------------------- the analytic 3-D shock
oblique = XMLUnstructuredGridReader(FileName=[os.path.join(args.data, "oblique_shock_unstructured.vtu")])
src = local(oblique)
n_exact = np.asarray(src.FieldData["ShockNormal"])
sensor3 = ShockSensor(Input=oblique, Velocity=["POINTS", "U"], Pressure=["POINTS", "p"], Density=["POINTS", "rho"])
weight3 = WeightFunction(Input=sensor3, Variables=["rho", "rhoU", "rhoE"], ComputePointWeight=1)
out3 = local(weight3)
save(weight3, "oblique_shock_sensors.vtu")
shock3 = np.asarray(out3.CellData["ShockCells"]) == 1
c3 = centroids(out3)[shock3]
_, _, vt = np.linalg.svd(c3 - c3.mean(axis=0))
angle = np.degrees(np.arccos(min(1.0, abs(np.dot(vt[-1], n_exact)))))
summary.append(("oblique shock (analytic, %d Gmsh tetrahedra)" % out3.GetNumberOfCells(), int(shock3.sum()),
                "shock plane %.2f deg from the exact one" % angle))

clusters3 = FeatureCluster(Input=weight3, SensorArray=["POINTS", "WeightFunction"], SensorRange=[1.5, 2.0])
surface3 = QuadricFit(Input=OutputPort(clusters3, 1), Domain=oblique, Template="Plane", ClusterId=0)
plane3 = local(surface3)
fit_angle = np.degrees(np.arccos(min(1.0, abs(np.dot(np.asarray(plane3.FieldData["Normal"]), n_exact)))))
save(surface3, "oblique_shock_surface.vtp")
summary.append(("oblique shock QuadricFit plane", int(plane3.GetNumberOfCells()),
                "fitted plane %.2f deg from the exact one" % fit_angle))

slice3 = Slice(Input=weight3)
slice3.SliceType.Origin = [0.5, 0.5, 0.5]
slice3.SliceType.Normal = [0, 0, 1]
shocks3 = Threshold(Input=weight3, Scalars=["CELLS", "ShockCells"], LowerThreshold=0.5, UpperThreshold=1.5)


def outline(display, view):
    display.Representation = "Outline"
    display.AmbientColor = [0, 0, 0]
    display.DiffuseColor = [0, 0, 0]
    ColorBy(display, None)


def translucent_shock(display, view):
    ColorBy(display, None)
    display.DiffuseColor = [0.2, 0.4, 1.0]
    display.Opacity = 0.35


def iso_view(view):
    view.ResetCamera()
    view.CameraPosition = [2.6, -1.6, 2.0]
    view.CameraFocalPoint = [0.5, 0.5, 0.45]
    view.CameraViewUp = [0, 0, 1]
    view.ResetCamera()


picture("oblique_shock_sensors.png",
        [(weight3, outline), (slice3, colored("WeightFunction", "CELLS", 1.0, 2.0, "Inferno (matplotlib)", "W")),
         (shocks3, translucent_shock)], iso_view,
        "Analytic 3-D oblique shock (M = 2.5): W on the mid-plane z = 0.5, shock cells in blue")
picture("oblique_shock_surface.png",
        [(weight3, outline), (slice3, colored("WeightFunction", "CELLS", 1.0, 2.0, "Inferno (matplotlib)", "W")),
         (surface3, surface_edges)], iso_view,
        "Analytic 3-D oblique shock: fitted, trimmed shock plane (%.2f deg from the exact one)" % fit_angle)

# ------------------------------------------------------------ the 3-D cone
cone_path = os.path.join(args.data, "cone20Ma2p5.vtu")
if os.path.exists(cone_path):
    from taylor_maccoll import cone_shock_angle
    cone = XMLUnstructuredGridReader(FileName=[cone_path])
    src = local(cone)
    half = float(np.asarray(src.FieldData["ConeHalfAngle"])[0])
    mach_c = float(np.asarray(src.FieldData["UpstreamMach"])[0])
    gamma_c = float(np.asarray(src.FieldData["Gamma"])[0])
    tip = np.asarray(src.FieldData["ConeTip"])
    reference = cone_shock_angle(mach_c, half, gamma_c)
    # The Mn = 1 band marks the centre of the captured shock (W's band sits on
    # its upstream side).
    weight_c = ShockSensor(Input=cone, Velocity=["POINTS", "U"], Pressure=["POINTS", "p"], Density=["POINTS", "rho"],
                           Gamma=gamma_c)
    clusters_c = FeatureCluster(Input=weight_c, SensorArray=["POINTS", "NormalMach"], SensorRange=[0.8, 1.2])
    surface_c = QuadricFit(Input=OutputPort(clusters_c, 1), Domain=cone, Template="Cone", ClusterId=0)
    fitted_cone = local(surface_c)
    got = float(np.asarray(fitted_cone.FieldData["HalfAngle"])[0])
    apex = np.asarray(fitted_cone.FieldData["Apex"])
    save(clusters_c, "cone20Ma2p5_sensors.vtu")
    save(surface_c, "cone20Ma2p5_shock_surface.vtp")
    summary.append(("cone20Ma2p5 (OpenFOAM, %d Gmsh tetrahedra) NormalMach 0.8-1.2, QuadricFit cone" % src.GetNumberOfCells(),
                    int(fitted_cone.GetNumberOfCells()),
                    "shock half-angle %.2f deg (Taylor-Maccoll %.2f deg), apex %.4f from the tip"
                    % (got, reference, np.linalg.norm(apex - tip))))
    # The medial sheet of the W = 1.5 isosurface, with the symmetry plane z = 0.
    w_c = WeightFunction(Input=weight_c, Variables=["rho", "rhoU", "rhoE"], ComputePointWeight=1)
    c_iso = Contour(Input=w_c, ContourBy=["POINTS", "WeightFunction"], Isosurfaces=[1.5], ComputeNormals=1)
    c_sheet = MedialAxisDelaunay(Input=c_iso, Domain=cone, SymmetryPlanes=[0, 0, 0, 0, 0, 1])
    cs = local(c_sheet)
    save(c_sheet, "cone20Ma2p5_medial_sheet.vtp")
    axis_c = np.asarray(fitted_cone.FieldData["AxisDirection"])
    v = np.asarray(cs.Points) - apex
    along = v @ axis_c
    d_cone = np.abs(np.linalg.norm(v - np.outer(along, axis_c), axis=1) * np.cos(np.radians(got)) - along * np.sin(np.radians(got)))
    cone_cell = np.median(np.cbrt(6 * np.sqrt(2) * np.asarray(local(CellSize(Input=cone, ComputeVolume=1)).CellData["Volume"])))
    summary.append(("cone20Ma2p5 MedialAxisDelaunay sheet of W = 1.5 (symmetry plane z = 0)", int(cs.GetNumberOfCells()),
                    "%d sheet(s); distance to the fitted cone max %.2f, mean %.2f cells"
                    % (len(np.asarray(cs.FieldData["SheetAreas"])), d_cone.max() / cone_cell, d_cone.mean() / cone_cell)))
    symmetry = Slice(Input=weight_c)
    symmetry.SliceType.Origin = [0.5, 0.0, 0.001]
    symmetry.SliceType.Normal = [0, 0, 1]

    def cone_view(view):
        view.ResetCamera()
        view.CameraPosition = [0.45, -0.6, 2.4]
        view.CameraFocalPoint = [0.45, 0.3, 0.0]
        view.CameraViewUp = [0, 1, 0]
        view.ResetCamera()

    def translucent_edges(display, view):
        surface_edges(display, view)
        display.Opacity = 0.3

    picture("cone20Ma2p5_shock_surface.png",
            [(symmetry, colored("p", "POINTS", 0.8, 2.4, "Viridis (matplotlib)", "p")), (surface_c, translucent_edges)],
            cone_view,
            "Mach 2.5, 20 deg cone (OpenFOAM): fitted conical shock %.2f deg (Taylor-Maccoll %.2f deg) over p on the symmetry plane"
            % (got, reference))

    picture("cone20Ma2p5_medial_sheet.png",
            [(symmetry, colored("p", "POINTS", 0.8, 2.4, "Viridis (matplotlib)", "p")),
             (c_sheet, colored("Radius", "POINTS", 0.0, 0.06, "Inferno (matplotlib)", "Radius"))],
            cone_view,
            "Medial sheet of the W = 1.5 isosurface (MedialAxisDelaunay, coloured by inscribed radius), "
            "%.2f cells on average from the fitted cone" % (d_cone.mean() / cone_cell))

    # ---- EmbeddedRemesh: the cone's mesh adapted to the fitted shock cone.
    adapted = EmbeddedRemesh(Input=cone, Surfaces=[surface_c], Mode="LocalCavity")
    am = local(adapted)
    save(adapted, "cone20Ma2p5_adapted.vtu")
    SaveData(os.path.join(args.output, "cone20Ma2p5_adapted.msh"), proxy=adapted)
    field = lambda d, n: float(np.asarray(d.FieldData[n])[0])
    summary.append(("cone20Ma2p5 EmbeddedRemesh (LocalCavity) on the fitted cone: %d -> %d nodes, %d -> %d cells"
                    % (src.GetNumberOfPoints(), am.GetNumberOfPoints(), src.GetNumberOfCells(), am.GetNumberOfCells()),
                    int(field(am, "SurfaceTriangles")),
                    "%d new cells, min / mean dihedral of new cells %.1f / %.1f deg, volume change %.1e"
                    % (field(am, "NewCells"), field(am, "MinDihedralAngleNew"), field(am, "MeanDihedralAngleNew"),
                       field(am, "RelativeVolumeChange"))))

    def dihedrals(d, mask=None):
        """Every dihedral angle of every 3-D cell (tetrahedra, pyramids,
        prisms, hexahedra: at each edge, 180 minus the angle between the
        outward normals of its two faces, a quad's normal the cross product of
        its diagonals, as ar::CellDihedralAngles does); with `mask` (a bool
        per cell), of those cells only."""
        from vtkmodules.util.numpy_support import vtk_to_numpy
        from vtkmodules.vtkCommonDataModel import VTK_HEXAHEDRON, VTK_PYRAMID, VTK_TETRA, VTK_WEDGE
        faces = {
            VTK_TETRA: [(1, 2, 3), (0, 3, 2), (0, 1, 3), (0, 2, 1)],
            VTK_PYRAMID: [(0, 3, 2, 1), (0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)],
            VTK_WEDGE: [(0, 1, 2), (3, 5, 4), (0, 3, 4, 1), (1, 4, 5, 2), (2, 5, 3, 0)],
            VTK_HEXAHEDRON: [(0, 4, 7, 3), (1, 2, 6, 5), (0, 1, 5, 4), (3, 7, 6, 2), (0, 3, 2, 1), (4, 5, 6, 7)],
        }
        P = np.asarray(d.Points, dtype=np.float64)
        vtk = d.VTKObject
        types = vtk_to_numpy(vtk.GetCellTypesArray())
        offsets = vtk_to_numpy(vtk.GetCells().GetOffsetsArray())
        conn = vtk_to_numpy(vtk.GetCells().GetConnectivityArray())
        out = []
        for t, fs in faces.items():
            idx = np.nonzero((types == t) & (True if mask is None else mask))[0]
            if len(idx) == 0:
                continue
            C = conn[offsets[idx][:, None] + np.arange(max(max(f) for f in fs) + 1)]  # the cells' nodes
            normals = []
            for f in fs:
                if len(f) == 3:
                    n = np.cross(P[C[:, f[1]]] - P[C[:, f[0]]], P[C[:, f[2]]] - P[C[:, f[0]]])
                else:
                    n = np.cross(P[C[:, f[2]]] - P[C[:, f[0]]], P[C[:, f[3]]] - P[C[:, f[1]]])
                normals.append(n / np.linalg.norm(n, axis=1)[:, None])
            for i in range(len(fs)):
                for j in range(i + 1, len(fs)):
                    if len(set(fs[i]) & set(fs[j])) == 2:  # the two faces share an edge
                        c = -np.einsum("ij,ij->i", normals[i], normals[j])
                        out.append(np.degrees(np.arccos(np.clip(c, -1, 1))))
        return np.concatenate(out) if out else np.zeros(0)

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    region = np.asarray(am.CellData["Region"])
    fig, ax = plt.subplots(figsize=(8, 4.5))
    bins = np.linspace(0, 180, 91)
    ax.hist(dihedrals(src), bins=bins, histtype="step", density=True, label="input (Gmsh)", color="0.4")
    ax.hist(dihedrals(am), bins=bins, histtype="step", density=True, label="adapted, all cells", color="tab:blue")
    ax.set_xlabel("dihedral angle (degrees)")
    ax.set_ylabel("density")
    ax.set_title("Cone case: dihedral angles before and after EmbeddedRemesh (paper Fig. 11b)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(args.output, "cone20Ma2p5_dihedral_histogram.png"), dpi=110)
    plt.close(fig)

    def cut(mesh_proxy):
        sl = Slice(Input=mesh_proxy, Crinkleslice=1)
        sl.SliceType.Origin = [0.5, 0.0, 0.25]
        sl.SliceType.Normal = [0, 0, 1]
        return sl

    def cut_edges(display, view):
        display.Representation = "Surface With Edges"
        display.EdgeColor = [0.1, 0.1, 0.2]

    picture("cone20Ma2p5_cut_input.png",
            [(cut(cone), colored("p", "POINTS", 0.8, 2.4, "Viridis (matplotlib)", "p")), (surface_c, translucent_edges)],
            cone_view, "Input mesh cut at z = 0.25 (crinkle), with the fitted shock cone")
    picture("cone20Ma2p5_cut_adapted.png",
            [(cut(adapted), colored("p", "POINTS", 0.8, 2.4, "Viridis (matplotlib)", "p")), (surface_c, translucent_edges)],
            cone_view, "Adapted mesh (EmbeddedRemesh, LocalCavity) cut at z = 0.25: the shock cone is a layer of faces")

    # ---- The prism variant (paper sections 4.1, 4.2): LayerType Prisms on
    # the same fitted cone. Prism layers on both sides of the embedded shock
    # cone (the defaults: 5 layers, growth 1.2, each side's stack half a
    # surface edge high), the quads of the stack's open side at S's border
    # closed by pyramids and thin closure tetrahedra, the rest of the cavity
    # refilled by TetGen.
    layers = 5
    prisms = EmbeddedRemesh(Input=cone, Surfaces=[surface_c], Mode="LocalCavity", LayerType="Prisms",
                            NumberOfLayers=layers, GrowthRatio=1.2)
    pm = local(prisms)
    save(prisms, "cone20Ma2p5_adapted_prisms.vtu")
    SaveData(os.path.join(args.output, "cone20Ma2p5_adapted_prisms.msh"), proxy=prisms)
    p_region = np.asarray(pm.CellData["Region"])
    summary.append(("cone20Ma2p5 EmbeddedRemesh with prism layers (LayerType Prisms, %d layers per side, first %.4f, "
                    "growth 1.2, stack %.4f per side): %d -> %d cells"
                    % (layers, field(pm, "FirstLayerThicknessUsed"), field(pm, "LayerStackHeight"),
                       src.GetNumberOfCells(), pm.GetNumberOfCells()),
                    int(field(pm, "SurfaceTriangles")),
                    "%d prisms, %d pyramids, %d closure tetrahedra, %d new tetrahedra (min / mean dihedral %.1f / %.1f "
                    "deg); layer cells: max aspect ratio %.1f, min dihedral %.1f deg; %d limited columns; volume change "
                    "%.1e" % (field(pm, "Prisms"), field(pm, "Pyramids"), field(pm, "LayerClosureTetrahedra"),
                              int((p_region == 1).sum()), field(pm, "MinDihedralAngleNew"),
                              field(pm, "MeanDihedralAngleNew"), field(pm, "MaxAspectRatioLayerCells"),
                              field(pm, "MinDihedralAngleLayerCells"), field(pm, "LimitedColumns"),
                              field(pm, "RelativeVolumeChange"))))

    # A cut across the axis (x = 0.5, crinkle: whole cells) coloured by kind
    # of cell: the shock cone is a half ring of prism layers.
    p_cut = Slice(Input=prisms, Crinkleslice=1)
    p_cut.SliceType.Origin = [0.5, 0.0, 0.0]
    p_cut.SliceType.Normal = [1, 0, 0]
    kinds = PythonCalculator(Input=p_cut, Expression="where(Region == 2, inputs[0].CellTypes, Region)",
                             ArrayAssociation="Cell Data", ArrayName="CellKind")

    def by_kind(display, view):
        display.Representation = "Surface With Edges"
        display.EdgeColor = [0.1, 0.1, 0.2]
        display.Ambient = 0.4   # (lighter shading of the faces seen at a grazing angle)
        display.Diffuse = 0.6
        ColorBy(display, ("CELLS", "CellKind"))
        lut = GetColorTransferFunction("CellKind")
        lut.InterpretValuesAsCategories = 1
        lut.Annotations = ["0", "kept tetrahedra", "1", "new tetrahedra (TetGen)", "13", "prisms", "14", "pyramids",
                           "10", "closure tetrahedra"]
        lut.IndexedColors = [0.8, 0.8, 0.8, 0.62, 0.78, 1.0, 1.0, 0.6, 0.2, 0.3, 0.75, 0.3, 0.85, 0.2, 0.25]
        display.SetScalarBarVisibility(view, True)
        bar = GetScalarBar(lut, view)
        bar.Title = "cell"
        bar.TitleColor = [0, 0, 0]
        bar.LabelColor = [0, 0, 0]

    def axial_view(y, z, scale):
        def camera(view):
            view.CameraPosition = [3.5, y, z]
            view.CameraFocalPoint = [0.5, y, z]
            view.CameraViewUp = [0, 0, 1]
            view.CameraParallelProjection = 1
            if scale is None:
                view.ResetCamera()
            else:
                view.CameraParallelScale = scale
        return camera

    picture("cone20Ma2p5_cut_prisms.png", [(kinds, by_kind)], axial_view(0.0, 0.35, None),
            "Cone adapted with prism layers (%d per side), cut across the axis at x = 0.5 (crinkle), seen from "
            "downstream: %d prisms, %d pyramids, %d closure tetrahedra" % (layers, field(pm, "Prisms"),
                                                                           field(pm, "Pyramids"),
                                                                           field(pm, "LayerClosureTetrahedra")))
    radius = 0.5 * np.tan(np.radians(got))  # the shock cone's radius at x = 0.5
    picture("cone20Ma2p5_cut_prisms_closeup.png", [(kinds, by_kind)], axial_view(0.0, radius, 0.06),
            "Close-up: %d prism layers on each side of the shock cone, first layer %.4f, growth 1.2 (the cells are "
            "whole: the dark band is the layer-0 prisms' faces on S seen at a grazing angle)"
            % (layers, field(pm, "FirstLayerThicknessUsed")))
    picture("cone20Ma2p5_cut_prisms_border.png", [(kinds, by_kind)],
            axial_view(-0.29, 0.15, 0.08),
            "Close-up at the shock surface's trimmed border: the layers' open side closed by pyramids (green) and "
            "closure tetrahedra (red), then TetGen's tetrahedra")

    # The dihedral angles of every cell type (paper Fig. 11b).
    p_types = np.asarray(pm.VTKObject.GetCellTypesArray())
    fig, axes = plt.subplots(1, 2, figsize=(13, 4.8))
    ax = axes[0]
    ax.hist(dihedrals(src), bins=bins, histtype="step", density=True, label="input (Gmsh tetrahedra)", color="0.4")
    ax.hist(dihedrals(am), bins=bins, histtype="step", density=True, label="adapted, tetrahedra only",
            color="tab:blue")
    ax.hist(dihedrals(pm), bins=bins, histtype="step", density=True, label="adapted with prism layers, all cells",
            color="tab:orange")
    ax.set_xlabel("dihedral angle (degrees)")
    ax.set_ylabel("density")
    ax.set_title("Cone case: all cells")
    ax.legend(fontsize=8)
    ax = axes[1]
    for label, mask, color in (("new tetrahedra (TetGen)", p_region == 1, "tab:blue"),
                               ("kept tetrahedra", p_region == 0, "0.4"),
                               ("prisms", p_types == 13, "tab:orange"),
                               ("pyramids", p_types == 14, "tab:green"),
                               ("closure tetrahedra", (p_region == 2) & (p_types == 10), "tab:red")):
        angles = dihedrals(pm, mask)
        ax.hist(angles, bins=bins, histtype="step", density=True, color=color,
                label="%s (%d cells, min %.1f deg)" % (label, int(mask.sum()), angles.min()))
    ax.set_xlabel("dihedral angle (degrees)")
    ax.set_ylabel("density (each kind of cell on its own)")
    ax.set_yscale("log")
    ax.set_ylim(1e-4, 2.0)
    ax.set_title("With prism layers, by kind of cell (paper Fig. 11b)")
    ax.legend(fontsize=8, loc="upper right")
    fig.tight_layout()
    fig.savefig(os.path.join(args.output, "cone20Ma2p5_dihedral_histogram_prisms.png"), dpi=110)
    plt.close(fig)

print_summary("| dataset | shock cells / medial points | check |", summary, args.output)
