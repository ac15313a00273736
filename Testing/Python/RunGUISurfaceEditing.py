"""GUI test: the real `paraview` executable under Xvfb runs
GUISurfaceEditingScript.py (wedge -> WeightFunction -> FeatureCluster ->
QuadricFit -> RemoveSelectedCells -> TrimSurface -> ExtendToPlane, shown over
the mesh) and saves a screenshot; then this script checks that the GUI ran the
pipeline (cells removed = cells selected, strips made) and that the picture
is not blank: many colours, a plausible fraction of non-background pixels,
and the red strips (Extended = 1) visible. The GUI is killed after 50 s.

    pvpython RunGUISurfaceEditing.py [fit|medial]

fit (default): the surface is QuadricFit's plane; medial: the medial sheet of
the WeightFunction isosurface from MedialAxisDelaunay."""
import os
import signal
import subprocess
import sys

import numpy as np

import artest
from artest import check

here = os.path.dirname(os.path.abspath(__file__))
source = sys.argv[1] if len(sys.argv) > 1 else "fit"
png = os.path.join(artest.OUTPUT_DIR, "GUISurfaceEditing_%s.png" % source)
for f in (png, png + ".txt"):
    if os.path.exists(f):
        os.remove(f)
env = artest.child_environment()
env["AR_GUI_SCREENSHOT"] = png
env["AR_GUI_SOURCE"] = source
cmd = ["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24 -noreset", "paraview", "--dr",
       "--script=" + os.path.join(here, "GUISurfaceEditingScript.py"), "--exit"]
artest.say("$ " + " ".join(cmd))
proc = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                        start_new_session=True)
try:
    output, _ = proc.communicate(timeout=50)
except subprocess.TimeoutExpired:
    os.killpg(proc.pid, signal.SIGKILL)  # xvfb-run, Xvfb and paraview
    output, _ = proc.communicate()
    artest.say(output[-3000:])
    check(False, "paraview exited within 50 s")
    artest.finish()
artest.say(output[-3000:])
check(proc.returncode == 0 and "Traceback" not in output, "paraview ran the script and exited cleanly (code %d)" % proc.returncode)
check(os.path.exists(png + ".txt"), "the script reached its end")
if os.path.exists(png + ".txt"):
    words = open(png + ".txt").read().split()
    stats = dict(zip(words[0::2], [int(w) for w in words[1::2]]))
    artest.say("     " + str(stats))
    check(stats["selected"] > 0 and stats["removed"] == stats["selected"],
          "GUI: RemoveSelectedCells removed the %d selected cells" % stats["selected"])
    check(stats["extended_edges"] > 0 and stats["extend"] > stats["trim"],
          "GUI: ExtendToPlane extended %d edges (%d -> %d cells)" % (stats["extended_edges"], stats["trim"], stats["extend"]))
check(os.path.exists(png), "screenshot saved")
if os.path.exists(png):
    from vtkmodules.vtkIOImage import vtkPNGReader
    from vtkmodules.util.numpy_support import vtk_to_numpy
    r = vtkPNGReader()
    r.SetFileName(png)
    r.Update()
    dims = r.GetOutput().GetDimensions()
    img = vtk_to_numpy(r.GetOutput().GetPointData().GetScalars())[:, :3].astype(int)
    check(dims[0] == 800 and dims[1] == 600, "screenshot is 800 x 600 (%d x %d)" % dims[:2])
    colours = len(np.unique(img[:, 0] * 65536 + img[:, 1] * 256 + img[:, 2]))
    background = img[0]  # a corner
    fraction = np.mean(np.abs(img - background).sum(axis=1) > 30)
    red = np.count_nonzero((img[:, 0] > 140) & (img[:, 1] < 90) & (img[:, 2] < 90))
    check(colours > 100, "picture has %d distinct colours" % colours)
    check(0.05 < fraction < 0.9, "non-background pixels: %.3f of the picture" % fraction)
    check(red > 1000, "the strips (Extended = 1, red) cover %d pixels" % red)
artest.finish()
