"""A second adaptation with prism layers on a mesh that has the first one's
layers (the paper's cycles, Fig. 3b-c: the shock moves a little, and the new
surface runs through the old stack). EmbeddedRemesh releases the old stack's
prisms and pyramids, which float inside the mesh (no face on the domain
boundary), so that the new cavity may take them (Remesh/ARLayerRelease.h);
layers that touch the boundary stay locked (TestEmbeddedRemeshHybrid).

Input: the analytic oblique shock (unit cube, h = 1/16) with QuadricFit's
plane as S; cycle 1 builds a stack on it; cycle 2 runs on cycle 1's output
(fields interpolated) with S moved along its normal.
a. S moved by 0.3 of the stack's height (inside the old stack): cycle 2
   builds its own stack; RemovedLayerCells equals cycle 1's prisms and
   pyramids (every layer of the old stack spans S, so the cavity takes all
   of them) and no old layer cell is left: every prism of cycle 2 stands on
   the moved plane (its points within the stack's height of it); the mesh
   valid (artest.check_valid_mesh against cycle 1's output: positive
   corners, conforming, the boundary kept, watertight, volume to 1e-9, the
   embedded triangles faces between two cells); the new tetrahedra at least
   10 degrees; p at the new points between cycle 1's extremes.
b. S moved far from the old stack (0.45, beyond the cavity's reach of it):
   RemovedLayerCells 0 and every prism and pyramid of cycle 1 is in cycle 2's
   output, the same cells at the same coordinates (keyed by their corners),
   with cycle 2's stack besides; the mesh valid.
"""
import numpy as np
from paraview.simple import *
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow

import artest
from artest import VTK_PYRAMID, VTK_TETRA, VTK_WEDGE, by_type, cells_of, check, coord_key, dihedral_angles

artest.load_plugin(globals())
messages = vtkStringOutputWindow()
vtkOutputWindow.SetInstance(messages)

LAYERS = 4
TOTAL = 0.04      # TotalThickness per side
EDGE = 0.05       # SurfaceEdgeLength (the mesh's edges are about 0.06-0.1)

oblique = XMLUnstructuredGridReader(FileName=[artest.data("oblique_shock_unstructured.vtu")])
weight = WeightFunction(Input=oblique, Variables=["p", "rho"], ComputePointWeight=1)
clusters = FeatureCluster(Input=weight, SensorArray=["POINTS", "WeightFunction"], SensorRange=[1.5, 2.0])
plane = QuadricFit(Input=OutputPort(clusters, 1), Domain=oblique, Template="Plane", ClusterId=0)
fit = artest.fetch(plane)
n = np.asarray(artest.field(fit, "Normal"))
o = np.asarray(artest.field(fit, "Origin"))


def remesh(mesh, surface):
    er = EmbeddedRemesh(Input=mesh, Surfaces=[surface], LayerType="Prisms", NumberOfLayers=LAYERS,
                        TotalThickness=TOTAL, SurfaceEdgeLength=EDGE)
    return er, artest.fetch(er), artest.fetch(er, 1)


def layer_cells(ds):
    """The prisms and pyramids of `ds`, each keyed by its corners' coordinates."""
    P = np.asarray(ds.Points, dtype=np.float64)
    types, cells = cells_of(ds)
    keys = set()
    for t in (VTK_WEDGE, VTK_PYRAMID):
        _, C = by_type(types, cells, t)
        keys |= {(t, coord_key(P, c)) for c in C}
    return keys


def moved(distance):
    t = Transform(Input=plane)
    t.Transform.Translate = list(distance * n)
    return t


er1, out1, emb1 = remesh(oblique, plane)
old = layer_cells(out1)
check(len(old) > 0 and not messages.GetOutput().strip(),
      "cycle 1: %d prisms and pyramids, no error or warning %r" % (len(old), messages.GetOutput()[-300:].strip()))
p1 = np.asarray(out1.PointData["p"])

# ---- a. S moved inside the old stack.
shift = 0.3 * TOTAL
er2, out2, emb2 = remesh(er1, moved(shift))
f = lambda name: artest.field(out2, name)[0]
check(not messages.GetOutput().strip(), "a: cycle 2 ran without an error or warning %r"
      % messages.GetOutput()[-300:].strip())
P2 = np.asarray(out2.Points, dtype=np.float64)
types2, cells2 = cells_of(out2)
_, W = by_type(types2, cells2, VTK_WEDGE)
check(f("RemovedLayerCells") == len(old),
      "a: the cavity took the whole old stack: RemovedLayerCells %d = cycle 1's %d prisms and pyramids"
      % (f("RemovedLayerCells"), len(old)))
reach = np.abs((P2[W] - (o + shift * n)) @ n).max()
check(len(W) > 0 and reach <= f("LayerStackHeight") * (1 + 1e-9) and not (layer_cells(out2) & old),
      "a: %d prisms, all on the moved plane's stack (farthest point %.4f <= its height %.4f), none of cycle 1's"
      % (len(W), reach, f("LayerStackHeight")))
artest.check_valid_mesh("a", out1, out2, emb2)
region = np.asarray(out2.CellData["Region"])
_, T = by_type(types2, cells2, VTK_TETRA)
tet_region = region[types2 == VTK_TETRA]
angles = dihedral_angles(P2, T[tet_region == 1], VTK_TETRA).min()
check(angles >= 10.0, "a: the new tetrahedra's smallest dihedral angle %.2f >= 10 deg" % angles)
p2 = np.asarray(out2.PointData["p"])
check(np.isfinite(p2).all() and p2.min() >= p1.min() - 1e-9 and p2.max() <= p1.max() + 1e-9,
      "a: p at every point within cycle 1's range [%.4f, %.4f] (got [%.4f, %.4f])"
      % (p1.min(), p1.max(), p2.min(), p2.max()))

# ---- b. S moved far from the old stack.
er3, out3, emb3 = remesh(er1, moved(0.45))
g = lambda name: artest.field(out3, name)[0]
kept = layer_cells(out3)
check(not messages.GetOutput().strip() and len(kept) > len(old),
      "b: cycle 2 ran without an error or warning and built its layers %r" % (messages.GetOutput()[-300:]))
check(g("RemovedLayerCells") == 0 and old <= kept and len(kept) > len(old),
      "b: the old stack is untouched: RemovedLayerCells %d, all %d of cycle 1's prisms and pyramids in the output "
      "(%d layer cells in all)" % (g("RemovedLayerCells"), len(old & kept), len(kept)))
artest.check_valid_mesh("b", out1, out3, emb3)
artest.finish()
