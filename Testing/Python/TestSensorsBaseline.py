"""Baseline comparison: the sensors' output arrays on the OpenFOAM wedge
(hexahedra) and on the Gmsh oblique-shock mesh (tetrahedra) against the
committed Testing/Baseline/*.vtu, array by array: NormalMach and
WeightFunction within 1e-9 relative (1e-12 absolute), ShockCells exactly.
The geometry (points, connectivity) must match exactly too.

To regenerate the baselines on purpose (after a deliberate change of the
algorithms, say why in the commit):
    AR_REGENERATE_BASELINES=1 ctest -R PySensorsBaseline
"""
import os

import numpy as np
from paraview.simple import *

import artest
from artest import check

artest.load_plugin(globals())

REGENERATE = os.environ.get("AR_REGENERATE_BASELINES", "") == "1"
ARRAYS = [("POINTS", "NormalMach", 1e-9), ("CELLS", "ShockCells", 0.0), ("CELLS", "WeightFunction", 1e-9)]

for data, baseline in (("wedge15Ma5.vtu", "SensorsWedge15Ma5.vtu"),
                       ("oblique_shock_unstructured.vtu", "SensorsObliqueShockUnstructured.vtu")):
    reader = XMLUnstructuredGridReader(FileName=[artest.data(data)])
    ss = ShockSensor(Input=reader, Velocity=["POINTS", "U"], Pressure=["POINTS", "p"], Density=["POINTS", "rho"])
    wf = WeightFunction(Input=ss, Variables=["rho", "rhoU", "rhoE"])
    keep = PassArrays(Input=wf, PointDataArrays=["NormalMach"], CellDataArrays=["ShockCells", "WeightFunction"],
                      FieldDataArrays=[])
    path = os.path.join(artest.BASELINE_DIR, baseline)
    if REGENERATE:
        SaveData(path, proxy=keep, DataMode="Binary", CompressorType="ZLib")
        print("regenerated %s" % path)
    out = artest.fetch(keep)
    ref = artest.fetch(XMLUnstructuredGridReader(FileName=[path]))
    check(np.array_equal(np.asarray(out.Points), np.asarray(ref.Points)), "%s: points equal the baseline" % data)
    check(out.GetNumberOfCells() == ref.GetNumberOfCells(), "%s: %d cells, baseline %d" % (data, out.GetNumberOfCells(), ref.GetNumberOfCells()))
    for association, name, rtol in ARRAYS:
        a = np.asarray((out.PointData if association == "POINTS" else out.CellData)[name], dtype=float)
        b = np.asarray((ref.PointData if association == "POINTS" else ref.CellData)[name], dtype=float)
        if a.shape != b.shape:
            check(False, "%s: %s has shape %s, baseline %s" % (data, name, a.shape, b.shape))
            continue
        worst = np.max(np.abs(a - b) / (rtol * np.abs(b) + 1e-12)) if rtol > 0 else float(np.sum(a != b))
        ok = np.allclose(a, b, rtol=rtol, atol=1e-12) if rtol > 0 else np.array_equal(a, b)
        check(ok, "%s: %s equals the baseline (%s)" % (data, name,
              "worst at %.3g of the tolerance" % worst if rtol > 0 else "%d values differ" % worst))

artest.finish()
