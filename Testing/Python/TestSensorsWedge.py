"""The sensors on real solver output: OpenFOAM rhoCentralFoam's wedge15Ma5
tutorial (Mach 5 over a 15 degree wedge, hexahedra, Data/wedge15Ma5.vtu).
The oblique shock from the wedge tip must come out at the theta-beta-Mach
angle (about 24.3 degrees) within 1 degree, from ShockCells (point data and
cell data, primitive and conserved variables) and from the ridge of W.
"""
import numpy as np
from paraview.simple import *

import artest
from artest import check
from theta_beta_mach import shock_angle

artest.load_plugin(globals())

reader = XMLUnstructuredGridReader(FileName=[artest.data("wedge15Ma5.vtu")])
src = artest.fetch(reader)
mach = artest.field(src, "UpstreamMach")[0]
wedge = artest.field(src, "WedgeAngle")[0]
gamma = artest.field(src, "Gamma")[0]
tip = artest.field(src, "WedgeTip")
beta = shock_angle(mach, wedge, gamma)
check(abs(beta - 24.32) < 0.05, "theta-beta-Mach reference: M = %.3f, theta = %.2f -> beta = %.3f deg" % (mach, wedge, beta))
centroids, longest = artest.cell_centroids(src)
h = np.median(longest)


def shock_line_angle(selected, label):
    """Fits a line to the selected cells' centroids (x, y) over the ramp, away
    from the tip and the outlet, and returns its angle to the x axis."""
    x, y = centroids[:, 0] - tip[0], centroids[:, 1] - tip[1]
    region = selected & (x > 0.03) & (x < 0.28)
    if region.sum() < 10:
        check(False, "%s: only %d shock cells over the ramp" % (label, region.sum()))
        return None
    normal, c = artest.fit_plane(np.c_[x[region], y[region]])  # a line: 2-D points
    angle = np.degrees(np.arctan2(abs(normal[0]), abs(normal[1])))
    # Every selected cell over the ramp is within two cells of the fitted line
    # (a captured shock is 2-3 cells thick).
    dist = np.abs((np.c_[x[region], y[region]] - c[:2]) @ normal[:2])
    check(dist.max() < 2.0 * h, "%s: shock cells within %.2f cells of the fitted line" % (label, dist.max() / h))
    return angle


cases = [
    ("point data, primitive",
     dict(Velocity=["POINTS", "U"], Pressure=["POINTS", "p"], Density=["POINTS", "rho"])),
    ("cell data, primitive",
     dict(Velocity=["CELLS", "U"], Pressure=["CELLS", "p"], Density=["CELLS", "rho"])),
    ("point data, conserved",
     dict(VariableSet=2, Density=["POINTS", "rho"], Momentum=["POINTS", "rhoU"], TotalEnergy=["POINTS", "rhoE"])),
]
for label, props in cases:
    ss = ShockSensor(Input=reader, Gamma=gamma, **props)
    out = artest.fetch(ss)
    shock = np.asarray(out.CellData["ShockCells"]) == 1
    angle = shock_line_angle(shock, label)
    if angle is not None:
        check(abs(angle - beta) < 1.0, "%s: %d shock cells, shock angle %.3f deg vs theta-beta-Mach %.3f deg"
              % (label, shock.sum(), angle, beta))
    # Nothing upstream of the shock: the flow is uniform there.
    x, y = centroids[:, 0] - tip[0], centroids[:, 1] - tip[1]
    upstream = (x < 0.0) | (y > np.tan(np.radians(beta)) * x + 3 * h)
    check(shock[upstream].sum() == 0, "%s: no shock cell in the uniform upstream flow (%d)" % (label, shock[upstream].sum()))
    Delete(ss)

# Weight function on the conserved variables: its ridge is the shock.
wf = WeightFunction(Input=reader, Variables=["rho", "rhoU", "rhoE"])
W = np.asarray(artest.fetch(wf).CellData["WeightFunction"])
check(W.min() >= 1.0 and W.max() <= 2.0, "W in [1, 2] (%.4f .. %.4f)" % (W.min(), W.max()))
x, y = centroids[:, 0] - tip[0], centroids[:, 1] - tip[1]
ridge = np.zeros(len(W), dtype=bool)
# In each column of cells over the ramp, the cell of highest W.
columns = np.round(x / h).astype(int)
for col in np.unique(columns[(x > 0.03) & (x < 0.28)]):
    in_col = np.where(columns == col)[0]
    ridge[in_col[np.argmax(W[in_col])]] = True
angle = shock_line_angle(ridge, "W ridge")
if angle is not None:
    check(abs(angle - beta) < 1.0, "W ridge: shock angle %.3f deg vs %.3f deg" % (angle, beta))
far = (x < -0.02) | (y > np.tan(np.radians(beta)) * x + 4 * h)
check(W[far].max() < 1.05, "W close to 1 in the uniform upstream flow (max %.4f)" % W[far].max())

artest.finish()
