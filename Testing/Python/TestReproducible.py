"""The same pipeline run three times in one process gives the same bits
(issue 14: threaded sums combined in a fixed order).

On the bundled OpenFOAM cone: ShockSensor (NormalMach at the points and
cells, ShockCells), WeightFunction (its cell and point arrays),
FeatureCluster (the medial points and their arrays), and AdaptToShocks with
tetrahedra and with prism layers (artest.contents: the adapted meshes' and
the fitted surfaces' points, cells and every point, cell and field array but
the Seconds* timings): every array of the
second and third run equal to the first's bit for bit. Before the
cell-to-point averages summed each point's cells in a fixed order, NormalMach
differed in 4,229 of 15,746 points between two runs in one process.

Then the same pipeline in two child processes, on 1 and on 2 threads
(VTK_SMP_MAX_THREADS): every array equal to the first run's bit for bit, so
the result does not depend on the number of threads either.
"""
import hashlib
import json
import os
import shutil
import subprocess
import sys

import numpy as np
from paraview.simple import *

import artest
from artest import check

artest.load_plugin(globals())
cone = XMLUnstructuredGridReader(FileName=[artest.data("cone20Ma2p5.vtu")])
cone.UpdatePipeline()  # (so that every run's WeightFunction gets the same default variables)


def run():
    sensor = ShockSensor(Input=cone)
    weight = WeightFunction(Input=cone, ComputePointWeight=1)
    clusters = FeatureCluster(Input=sensor)
    tets = AdaptToShocks(Input=cone)
    prisms = AdaptToShocks(Input=cone, LayerType=1)
    result = {}
    for label, proxy, port in (("sensor:", sensor, 0), ("weight:", weight, 0), ("medial:", clusters, 1),
                               ("adapted:", tets, 0), ("surfaces:", tets, 1), ("layers:", prisms, 0)):
        result.update((label + name, value) for name, value in artest.contents(artest.fetch(proxy, port)).items())
    return result


if "--worker" in sys.argv:  # a child: one run, its digests to the file given
    with open(sys.argv[sys.argv.index("--worker") + 1], "w") as f:
        json.dump({k: hashlib.sha1(v).hexdigest() for k, v in run().items()}, f)
    sys.exit(0)

first = run()
check(len(first) > 20 and any(k.endswith("NormalMach") for k in first),
      "the first run: %d arrays (sensor, weight, medial points, adapted meshes)" % len(first))
for i in (2, 3):
    again = run()
    differing = sorted(k for k in set(first) | set(again) if again.get(k) != first.get(k))
    check(not differing, "run %d: every one of the %d arrays equal to the first run's bit for bit%s"
          % (i, len(first), "" if not differing else " (differing or missing: %s)" % ", ".join(differing[:8])))

digests = {k: hashlib.sha1(v).hexdigest() for k, v in first.items()}
pvpython = shutil.which("pvpython") or sys.executable
for threads in (1, 2):
    path = os.path.join(artest.OUTPUT_DIR, "reproducible_%d_threads.json" % threads)
    if os.path.exists(path):
        os.remove(path)
    env = dict(artest.child_environment(), VTK_SMP_BACKEND_IN_USE="STDThread", VTK_SMP_MAX_THREADS=str(threads))
    rc = subprocess.run([pvpython, os.path.abspath(__file__), "--worker", path], env=env).returncode
    other = json.load(open(path)) if rc == 0 and os.path.exists(path) else {}
    differing = sorted(k for k in set(digests) | set(other) if other.get(k) != digests.get(k))
    check(rc == 0 and not differing, "%d thread%s (a child process): every one of the %d arrays equal to the first "
          "run's bit for bit%s" % (threads, "" if threads == 1 else "s", len(digests),
                                   "" if not differing else " (differing or missing: %s)" % ", ".join(differing[:8])))
artest.finish()
