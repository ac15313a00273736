"""EmbeddedRemesh keeps the boundary patches: the OpenFOAM cone's mesh as a
multiblock the way ParaView's OpenFOAM reader gives it (internalMesh plus a
"boundary" block of named patches, here classified from the geometry:
inlet, outlet, symmetry, farfield, cone), remeshed around the fitted shock
cone. The volume leaf is remeshed; every patch leaf comes out identical to
its input; the patches cover exactly the new volume's boundary faces; and
the adapted mesh written as Gmsh MSH 2.2 has one physical group per patch
with the input's face counts.
"""
import os

import numpy as np
from paraview.simple import *
from paraview import servermanager
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet
from vtkmodules.vtkCommonDataModel import vtkCompositeDataSet
from vtkmodules.vtkFiltersGeometry import vtkGeometryFilter

import artest
from artest import check

artest.load_plugin(globals())

cone = XMLUnstructuredGridReader(FileName=[artest.data("cone20Ma2p5.vtu")])




patches = artest.CONE_PATCHES
volume = artest.fetch(cone).VTKObject
mb, names = artest.openfoam_multiblock(volume, artest.cone_patches, patches)
boundary = mb.GetBlock(1)
counts = {n: int((names == n).sum()) for n in patches}
check(all(n > 0 for n in counts.values()), "the cone's boundary in 5 patches: %s" % counts)
source = PVTrivialProducer()
source.GetClientSideObject().SetOutput(mb)

fit = artest.cone_shock_fit(cone)
adapted = EmbeddedRemesh(Input=source, Surfaces=[fit])
adapted.UpdatePipeline()
out = servermanager.Fetch(adapted)
check(out.IsA("vtkMultiBlockDataSet") and out.GetNumberOfBlocks() == 2, "the output is a multiblock of the same shape")
new_volume = out.GetBlock(0)
region = vtk_to_numpy(new_volume.GetCellData().GetArray("Region"))
check((region == 1).sum() > 1000 and new_volume.GetNumberOfCells() != volume.GetNumberOfCells(),
      "internalMesh remeshed: %d -> %d cells, %d new" % (volume.GetNumberOfCells(), new_volume.GetNumberOfCells(), (region == 1).sum()))


def keys(points, tris):
    k = np.round(points[tris] * 1e9).astype(np.int64)
    order = np.lexsort((k[:, :, 2], k[:, :, 1], k[:, :, 0]), axis=1)
    return set(map(tuple, np.take_along_axis(k, order[:, :, None], axis=1).reshape(-1, 9)))


out_boundary = out.GetBlock(1)
covered = set()
for i, name in enumerate(patches):
    pd = out_boundary.GetBlock(i)
    same = (out_boundary.GetMetaData(i).Get(vtkCompositeDataSet.NAME()) == name and pd.GetNumberOfCells() == counts[name]
            and np.array_equal(vtk_to_numpy(pd.GetPolys().GetConnectivityArray()),
                               vtk_to_numpy(boundary.GetBlock(i).GetPolys().GetConnectivityArray())))
    check(same, "patch %s passes through unchanged (%d faces)" % (name, pd.GetNumberOfCells()))
    covered |= keys(vtk_to_numpy(pd.GetPoints().GetData()).astype(np.float64),
                    vtk_to_numpy(pd.GetPolys().GetConnectivityArray()).reshape(-1, 3))
g2 = vtkGeometryFilter()
g2.SetInputData(new_volume)
g2.Update()
new_skin = g2.GetOutput()
new_faces = keys(vtk_to_numpy(new_skin.GetPoints().GetData()).astype(np.float64),
                 vtk_to_numpy(new_skin.GetPolys().GetConnectivityArray()).reshape(-1, 3))
check(new_faces == covered, "the patches cover exactly the new volume's %d boundary faces" % len(new_faces))

# The adapted mesh for the solver: one physical group per patch.
path = os.path.join(artest.OUTPUT_DIR, "cone_adapted_patches.msh")
if os.path.exists(path):
    os.remove(path)
SaveData(path, proxy=adapted)
text = open(path).read() if os.path.exists(path) else ""
block = text.split("$PhysicalNames")[1].split("$EndPhysicalNames")[0].split("\n")[2:-1] if "$PhysicalNames" in text else []
groups = {line.split()[2].strip('"'): (int(line.split()[0]), int(line.split()[1])) for line in block}
check(set(patches) <= set(groups), "the .msh has a physical group per patch: %s" % sorted(groups))
elements = text.split("$Elements")[1].split("$EndElements")[0].split("\n")[2:-1] if "$Elements" in text else []
per_group = {}
for line in elements:
    f = line.split()
    per_group[int(f[3])] = per_group.get(int(f[3]), 0) + 1
check(all(per_group.get(groups[n][1], 0) == counts[n] for n in patches if n in groups),
      "each patch group has the input's number of faces")
artest.finish()
