"""Bad input through paraview.simple: a clear error naming the problem, the
input passed through unchanged (no new array), and no crash. (The C++ test
TestSensors covers every case one by one; this checks the same contract as a
pvpython user meets it.)
"""
import numpy as np
from paraview.simple import *
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow

import artest
from artest import check

artest.load_plugin(globals())
messages = vtkStringOutputWindow()
vtkOutputWindow.SetInstance(messages)


def refused(proxy, fragment, new_arrays, label):
    before = len(messages.GetOutput())
    out = artest.fetch(proxy)
    text = messages.GetOutput()[before:]
    check(fragment in text, "%s: error says '%s'" % (label, fragment))
    present = [a for a in new_arrays if a in out.PointData.keys() or a in out.CellData.keys()]
    check(not present, "%s: no output array added (%s)" % (label, present))
    return out


wedge = XMLUnstructuredGridReader(FileName=[artest.data("wedge15Ma5.vtu")])
n_cells = artest.fetch(wedge).GetNumberOfCells()

out = refused(ShockSensor(Input=wedge, Velocity=["POINTS", "U"], Pressure=["POINTS", "pressure"], Density=["POINTS", "rho"]),
              "Pressure array 'pressure' is not a point or cell array", ["NormalMach", "ShockCells"], "missing array")
check(out.GetNumberOfCells() == n_cells, "missing array: the input passes through (%d cells)" % out.GetNumberOfCells())

refused(ShockSensor(Input=wedge, Velocity=["POINTS", "p"], Pressure=["POINTS", "p"], Density=["POINTS", "rho"]),
        "has 1 components; it needs 3", ["NormalMach"], "wrong components")

negative = Calculator(Input=wedge, ResultArrayName="p", Function="p - 2")  # p is 1 upstream
refused(ShockSensor(Input=negative, Velocity=["POINTS", "U"], Pressure=["POINTS", "p"], Density=["POINTS", "rho"]),
        "must be positive everywhere", ["NormalMach"], "negative pressure")

bad = PythonCalculator(Input=wedge, ArrayName="bad", Expression="rho / (points[:,0] > 0)")  # Inf for x <= 0
refused(WeightFunction(Input=bad, Variables=["rho", "bad"]), "'bad' holds NaN or Inf", ["WeightFunction"], "Inf")

nothing = Threshold(Input=wedge, Scalars=["CELLS", "p"], LowerThreshold=1e6, UpperThreshold=1e7)
refused(ShockSensor(Input=nothing, Velocity=["POINTS", "U"], Pressure=["POINTS", "p"], Density=["POINTS", "rho"]),
        "The input mesh is empty", ["NormalMach"], "empty mesh")

surface = ExtractSurface(Input=wedge)
surface_grid = AppendDatasets(Input=surface)  # polygons as an unstructured grid
refused(WeightFunction(Input=surface_grid, Variables=["rho"]), "no linear 3-D cells", ["WeightFunction"], "2-D cells only")

# No selection in ParaView means its default, every point and cell array
# (the C++ test covers a selection that resolves to nothing).
W = np.asarray(artest.fetch(WeightFunction(Input=wedge)).CellData["WeightFunction"])
check(W.min() >= 1.0 and W.max() <= 2.0 and W.max() > 1.9, "default selection (all arrays): W in [1, 2]")

# And after all that, the same filters still work on good input.
good = artest.fetch(ShockSensor(Input=wedge, Velocity=["POINTS", "U"], Pressure=["POINTS", "p"], Density=["POINTS", "rho"]))
check(np.asarray(good.CellData["ShockCells"]).sum() > 50, "good input afterwards: shock cells found")

artest.finish()
