"""Child of TestBadInput.py: EmbeddedRemesh (FullDomain, SurfaceSizeFactor
0.02 on the analytic oblique shock, under the job-size cap) with the address
space limited to what the process holds plus argv[1] MB, so that an
allocation of the core fails with std::bad_alloc. Prints the filter's
messages and the output's cell count; it must end normally (exit 0), not
abort.

(At SurfaceSizeFactor 0.04, about 1.8e6 elements and 530 MB, the core's work
before the refill now fits in the heap the process already holds, even with
1 MB to spare: only TetGen's process, which inherits the limit, runs out, and
says so as a TetGen failure, which is not what this checks.)"""
import resource
import sys

from paraview.simple import *
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow

import artest

artest.load_plugin(globals())
messages = vtkStringOutputWindow()
vtkOutputWindow.SetInstance(messages)
oblique = XMLUnstructuredGridReader(FileName=[artest.data("oblique_shock_unstructured.vtu")])
weight = WeightFunction(Input=oblique, Variables=["p", "rho"], ComputePointWeight=1)
clusters = FeatureCluster(Input=weight, SensorArray=["POINTS", "WeightFunction"], SensorRange=[1.5, 2.0])
plane = QuadricFit(Input=OutputPort(clusters, 1), Domain=oblique, Template="Plane", ClusterId=0)
n_in = artest.fetch(oblique).GetNumberOfCells()
artest.fetch(plane)
with open("/proc/self/status") as f:
    size_kb = int([line for line in f if line.startswith("VmSize")][0].split()[1])
resource.setrlimit(resource.RLIMIT_AS, (size_kb * 1024 + int(sys.argv[1]) * 1024 * 1024, resource.RLIM_INFINITY))
out = artest.fetch(EmbeddedRemesh(Input=oblique, Surfaces=[plane], Mode="FullDomain", SurfaceSizeFactor=0.02))
artest.say("INPUT CELLS %d OUTPUT CELLS %d" % (n_in, out.GetNumberOfCells()))
artest.say("MESSAGES " + messages.GetOutput().replace("\n", " "))
