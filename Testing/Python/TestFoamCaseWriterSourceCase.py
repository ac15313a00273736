"""The OpenFOAM case writer with a SourceCase: OpenFOAM's rhoCentralFoam
tutorial wedge15Ma5 (2-D, 4800 hexahedra; patches inlet, outlet, bottom and
top symmetryPlane, obstacle, defaultFaces empty) after blockMesh and 20
solver steps (written at 0.001 and 0.002), read by ParaView's OpenFOAM
reader at its latest time.

(a) The source read back and written unmodified (SaveData with SourceCase):
    patch names, types, inGroups and face counts equal the source's; the
    points equal the source's (float exact: the reader reads floats) in
    order; owner and neighbour equal the source's and each face has the
    source face's points; every source field of 0.002 is in 0/ with the
    source's class and dimensions, its cell values exactly the source's
    (the source's values differ between 0.001 and 0.002, so the time read
    matters), its boundary types the source's, its uniform values the
    source's text, its nonuniform `value` lists one value per face equal to
    the cell next to the face (the documented rewrite); system/ and
    constant/thermophysicalProperties are copies; checkMesh "Mesh OK.".
(b) The source remeshed by EmbeddedRemesh in 2-D around the shock plane
    (QuadricFit on the converged Data/wedge15Ma5.vtu, the same blockMesh
    mesh) and written with the SourceCase: patch names, types and inGroups
    the source's; every patch whose source faces are all still there has
    the source's face count (inlet, bottom and one more at least); every
    source field in 0/; at every kept cell (Region 0, matched to its source
    cell by centroid) every field's value exactly the source's; every
    nonuniform boundary list as long as its patch; checkMesh "Mesh OK.",
    2-D. Then rhoCentralFoam runs 10 steps on it (deltaT, endTime and
    writeInterval set in the copied controlDict) without failure, and the
    result (time 0.0001) reads back in ParaView's OpenFOAM reader with our
    cell count and finite, positive p and T.
(c) A malformed SourceCase boundary file and a SourceTime the source does
    not have: an error naming the cause, nothing written.
(d) A hand-written source time 0 (SourceTime "0"): `value $internalField`,
    a quoted regular expression, a group name (inGroups), a top-level
    macro, inletOutlet and mixed entries with nonuniform lists, a field the
    input has no array for: the entries found as OpenFOAM finds them,
    constraint types kept, `$internalField` replaced by the uniform value,
    the value list from the cells next to the faces, refValue uniform at its
    mean, the missing field uniform; foamDictionary -expand reads every field
    and rhoCentralFoam runs 2 steps on the case.
"""
import filecmp
import os
import re
import shutil
import time

import numpy as np
from paraview.simple import *
from paraview import servermanager
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.numpy_interface import dataset_adapter as dsa
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow

import artest
import foamcase
from artest import check

BASHRC = foamcase.bashrc("the OpenFOAM case writer's source case")
TUTORIAL = foamcase.tutorial("compressible/rhoCentralFoam/wedge15Ma5")
artest.load_plugin(globals())
messages = vtkStringOutputWindow()
vtkOutputWindow.SetInstance(messages)
OUT = os.path.join(artest.OUTPUT_DIR, "FoamCaseWriterSourceCase")
shutil.rmtree(OUT, ignore_errors=True)
os.makedirs(OUT)

# ---- The source case: blockMesh and 20 steps of rhoCentralFoam.
SRC = os.path.join(OUT, "source")
if not foamcase.solved_tutorial(BASHRC, TUTORIAL, SRC, "0.002", "0.001", check):
    artest.finish()
LATEST = "0.002"
FIELDS = sorted(f for f in os.listdir(os.path.join(SRC, LATEST))
                if os.path.isfile(os.path.join(SRC, LATEST, f)) and foamcase.header(os.path.join(SRC, LATEST, f))["class"].startswith("vol"))
check(FIELDS == ["T", "U", "p", "rho"], "source case: fields at %s %s" % (LATEST, FIELDS))
open(os.path.join(SRC, "source.foam"), "w").close()

reader = OpenFOAMReader(FileName=os.path.join(SRC, "source.foam"))
reader.MeshRegions = ["internalMesh"] + [r for r in reader.MeshRegions.Available if r.startswith("patch/")]
reader.CellArrays = FIELDS
scene = GetAnimationScene()
scene.UpdateAnimationUsingDataTimeSteps()
scene.AnimationTime = float(LATEST)
reader.UpdatePipeline(float(LATEST))

s_points, s_faces, s_owner, s_neighbour, s_boundary = foamcase.read_polymesh(SRC)
s_fields = {f: foamcase.read_field(os.path.join(SRC, LATEST, f)) for f in FIELDS}
early = foamcase.read_field(os.path.join(SRC, "0.001", "p"))[2]
check(not np.array_equal(early, s_fields["p"][2]), "source case: p differs between 0.001 and 0.002")


def groups(entries):
    g = entries.get("inGroups", "")
    return g[g.find("("):].strip("()").split() if "(" in g else []


def patch_table(boundary):
    return [(name, e["type"], groups(e), int(e["nFaces"])) for name, e in boundary]


def checkmesh(case, label):
    rc, log = foamcase.run(BASHRC, case, "checkMesh")
    ok = rc == 0 and "Mesh OK." in log and "Failed" not in log
    check(ok and "Mesh has 2 solution (non-empty) directions" in log,
          "%s: checkMesh says 'Mesh OK.' with 2 solution directions (exit %d)" % (label, rc))
    if not ok:
        artest.say(log[log.find("Checking"):][-3000:])


def save(proxy, label, **props):
    case = os.path.join(OUT, label)
    before = len(messages.GetOutput())
    t0 = time.time()
    SaveData(os.path.join(case, label + ".foam"), proxy=proxy, SourceCase=SRC, **props)
    artest.say("    %s: written in %.2f s" % (label, time.time() - t0))
    text = messages.GetOutput()[before:]
    check(os.path.isdir(os.path.join(case, "constant", "polyMesh")) and "ERROR" not in text,
          "%s: case written with SourceCase, no error %r" % (label, text[-300:]))
    return case


# ================================================ (a) unmodified round trip
case = save(reader, "roundtrip")
points, faces, owner, neighbour, boundary = foamcase.read_polymesh(case)
check(patch_table(boundary) == patch_table(s_boundary),
      "round trip: patches (name, type, inGroups, nFaces) %s = the source's" % patch_table(boundary))
check(points.shape == s_points.shape and np.array_equal(points.astype(np.float32), s_points.astype(np.float32)),
      "round trip: %d points equal the source's in order (float exact)" % len(points))
check(np.array_equal(owner, s_owner) and np.array_equal(neighbour, s_neighbour),
      "round trip: owner and neighbour equal the source's (%d faces, %d internal)" % (len(owner), len(neighbour)))
check(all(sorted(a) == sorted(b) for a, b in zip(faces, s_faces)) and len(faces) == len(s_faces),
      "round trip: every face has the source face's points")
check(sorted(os.listdir(os.path.join(case, "0"))) == FIELDS, "round trip: the source's fields in 0/: %s" % sorted(os.listdir(os.path.join(case, "0"))))
n_internal = len(neighbour)
starts = {name: (int(e["startFace"]), int(e["nFaces"])) for name, e in boundary}
for f in FIELDS:
    cls, dims, values, patches = foamcase.read_field(os.path.join(case, "0", f))
    scls, sdims, svalues, spatches = s_fields[f]
    check(cls == scls and dims == sdims, "round trip: %s is a %s with dimensions %s (the source's)" % (f, cls, dims))
    check(np.array_equal(np.asarray(values, np.float32), np.asarray(svalues, np.float32)),
          "round trip: %s's %d cell values are exactly the source's at %s" % (f, len(values), LATEST))
    for p, entry in spatches.items():
        stype = re.search(r"type\s+(\w+);", entry).group(1)
        ours = patches.get(p, "")
        otype = re.search(r"type\s+(\w+);", ours)
        ok = otype is not None and otype.group(1) == stype
        uniform = re.search(r"value\s+(uniform[^;]*);", entry)
        if uniform:
            ok &= re.search(r"value\s+(uniform[^;]*);", ours) is not None and \
                re.search(r"value\s+(uniform[^;]*);", ours).group(1) == uniform.group(1)
        listed = foamcase.nonuniform_values(entry)
        what = ""
        if listed is not None:
            got = foamcase.nonuniform_values(ours)
            start, n = starts[p]
            ok &= got is not None and len(got) == n and np.array_equal(
                np.asarray(got, np.float32), np.asarray(values, np.float32)[owner[start:start + n]])
            what = ", its %d face values those of the cells next to the faces" % n
        check(ok, "round trip: %s on %s: type %s%s%s" % (f, p, stype, ", value " + uniform.group(1) if uniform else "", what))
same = filecmp.dircmp(os.path.join(SRC, "system"), os.path.join(case, "system"))
check(not same.left_only and not same.right_only and not same.diff_files and
      filecmp.cmp(os.path.join(SRC, "constant", "thermophysicalProperties"),
                  os.path.join(case, "constant", "thermophysicalProperties"), shallow=False),
      "round trip: system/ and constant/thermophysicalProperties are the source's")
checkmesh(case, "round trip")

# ================================================ (b) remeshed in 2-D, then solved
converged = XMLUnstructuredGridReader(FileName=[artest.data("wedge15Ma5.vtu")])
weight = WeightFunction(Input=converged, Variables=["rho", "rhoU", "rhoE"], ComputePointWeight=1)
clusters = FeatureCluster(Input=weight, SensorArray=["POINTS", "WeightFunction"], SensorRange=[1.5, 2.0])
fit = QuadricFit(Input=OutputPort(clusters, 1), Domain=converged, Template="Plane", ClusterId=0)
adapted = EmbeddedRemesh(Input=reader, Surfaces=[fit])
adapted.UpdatePipeline(float(LATEST))
out = servermanager.Fetch(adapted)
mesh = out.GetBlock(0)
region = vtk_to_numpy(mesh.GetCellData().GetArray("Region"))
check((region == 0).sum() > 1000 and (region == 1).sum() > 1000,
      "adapted: EmbeddedRemesh kept %d cells and made %d" % ((region == 0).sum(), (region == 1).sum()))
case = save(adapted, "adapted")
points, faces, owner, neighbour, boundary = foamcase.read_polymesh(case)
check([t[:3] for t in patch_table(boundary)] == [t[:3] for t in patch_table(s_boundary)],
      "adapted: patch names, types and inGroups %s = the source's" % [t[:3] for t in patch_table(boundary)])


def nearest(points, queries):
    """Index of and distance to the nearest of `points` for each query (vtkStaticPointLocator)."""
    from vtkmodules.vtkCommonDataModel import vtkPolyData, vtkStaticPointLocator
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.util.numpy_support import numpy_to_vtk
    pts = vtkPoints()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(points, dtype=np.float64), deep=True))
    cloud = vtkPolyData()
    cloud.SetPoints(pts)
    loc = vtkStaticPointLocator()
    loc.SetDataSet(cloud)
    loc.BuildLocator()
    idx = np.array([loc.FindClosestPoint(q) for q in queries], dtype=np.int64)
    return idx, np.linalg.norm(np.asarray(points)[idx] - queries, axis=1)


def patch_centres(points, faces, boundary, n_internal):
    """{patch: (n, 3) face centres}."""
    out, start = {}, n_internal
    for name, e in boundary:
        n = int(e["nFaces"])
        out[name] = np.array([points[faces[i]].mean(axis=0) for i in range(start, start + n)])
        start += n
    return out


TOL = 1e-9  # the kept faces and cells are the source's to float precision (coordinates ~0.1)
ours = patch_centres(points, faces, boundary, len(neighbour))
theirs = patch_centres(s_points, s_faces, s_boundary, len(s_neighbour))
kept = [p for p in theirs if len(ours[p]) and np.all(nearest(ours[p], theirs[p])[1] < TOL)]
check(set(["inlet", "bottom"]) <= set(kept) and len(kept) >= 3 and all(len(ours[p]) == len(theirs[p]) for p in kept),
      "adapted: the patches whose source faces are all kept (%s) have the source's face counts %s"
      % (kept, {p: len(ours[p]) for p in kept}))
check(sorted(os.listdir(os.path.join(case, "0"))) == FIELDS, "adapted: the source's fields in 0/")
# Kept cells matched to source cells by centroid.


def centroids(grid):
    """Vertex centroids of a grid's cells, in double precision."""
    pts = vtk_to_numpy(grid.GetPoints().GetData()).astype(np.float64)
    offsets = vtk_to_numpy(grid.GetCells().GetOffsetsArray())
    conn = vtk_to_numpy(grid.GetCells().GetConnectivityArray())
    return np.array([pts[conn[offsets[c]:offsets[c + 1]]].mean(axis=0) for c in range(len(offsets) - 1)])


centre = centroids(servermanager.Fetch(reader).GetBlock(0))
new_centre = centroids(mesh)
match, distance = nearest(centre, new_centre[region == 0])
check(np.all(distance < TOL), "adapted: every kept cell has a source cell at its centroid (max distance %.2g)" % distance.max())
starts = {name: int(e["nFaces"]) for name, e in boundary}
for f in FIELDS:
    cls, dims, values, patches = foamcase.read_field(os.path.join(case, "0", f))
    svalues = s_fields[f][2]
    check(len(values) == len(region) and
          np.array_equal(np.asarray(values, np.float32)[region == 0], np.asarray(svalues, np.float32)[match]),
          "adapted: %s (%s) at the %d kept cells exactly the source's" % (f, cls, (region == 0).sum()))
    lengths = {p: len(foamcase.nonuniform_values(e)) for p, e in patches.items() if foamcase.nonuniform_values(e) is not None}
    check(all(lengths[p] == starts[p] for p in lengths),
          "adapted: %s's nonuniform boundary lists are as long as their patches %s" % (f, lengths))
checkmesh(case, "adapted")
for command in ("foamDictionary -entry deltaT -set 1e-05 system/controlDict",
                "foamDictionary -entry endTime -set 0.0001 system/controlDict",
                "foamDictionary -entry writeInterval -set 5e-05 system/controlDict"):
    foamcase.run(BASHRC, case, command)
t0 = time.time()
rc, log = foamcase.run(BASHRC, case, "rhoCentralFoam")
steps = len(re.findall(r"^Time = ", log, re.M))
check(rc == 0 and log.rstrip().endswith("End") and steps == 10,
      "adapted: rhoCentralFoam ran %d steps and ended (exit %d, %.1f s)" % (steps, rc, time.time() - t0))
if rc != 0:
    artest.say(log[-2000:])
result = OpenFOAMReader(FileName=os.path.join(case, "adapted.foam"))
result.MeshRegions = ["internalMesh"]
result.UpdatePipelineInformation()
times = list(result.TimestepValues)
result.UpdatePipeline(max(times) if times else 0.0)
result_data = servermanager.Fetch(result)
back = dsa.WrapDataObject(result_data.GetBlock(0)) if result_data.GetNumberOfBlocks() else None
ok = back is not None and back.GetNumberOfCells() == len(region)
arrays = {}
if ok:
    arrays = {n: np.asarray(back.CellData[n]) for n in FIELDS if n in back.CellData.keys()}
check(ok and times and abs(max(times) - 1e-4) < 1e-9 and sorted(arrays) == FIELDS and
      all(np.all(np.isfinite(a)) for a in arrays.values()) and arrays["p"].min() > 0 and arrays["T"].min() > 0,
      "adapted: the solution at t = %s reads back in ParaView: %s cells, fields %s finite, p and T positive"
      % (max(times) if times else None, back.GetNumberOfCells() if back is not None else None, sorted(arrays)))


# ================================================ (d) boundary entries as people write them
# A source whose time 0 uses a `$internalField` value, a quoted regular
# expression, a group name, a top-level macro, nonuniform refValue / value
# lists and a field (alpha) the input has no array for.
HAND = os.path.join(OUT, "handwritten_source")
shutil.copytree(SRC, HAND, ignore=shutil.ignore_patterns("0*", "log.*"))
os.makedirs(os.path.join(HAND, "0"))
HEAD = "FoamFile { version 2.0; format ascii; class %s; object %s; }\n"
outlet_T = " ".join("%g" % (1 + 0.01 * i) for i in range(40))
outlet_U = " ".join("(%g 0 0)" % (1 + 0.1 * i) for i in range(40))
HAND_FIELDS = {
    "p": HEAD % ("volScalarField", "p") + """dimensions [1 -1 -2 0 0 0 0];
internalField uniform 1;
boundaryField
{
    inlet { type fixedValue; value $internalField; }
    "(outlet|obstacle)" { type zeroGradient; }
    symmetryPlane { type symmetryPlane; }
    defaultFaces { type empty; }
}
""",
    "T": HEAD % ("volScalarField", "T") + """Tinlet 1;
dimensions [0 0 0 1 0 0 0];
internalField uniform 1;
boundaryField
{
    inlet { type fixedValue; value uniform $Tinlet; }
    outlet { type inletOutlet; inletValue uniform 1; value nonuniform List<scalar> 40(%s); }
    ".*" { type zeroGradient; }
}
""" % outlet_T,
    "U": HEAD % ("volVectorField", "U") + """dimensions [0 1 -1 0 0 0 0];
internalField uniform (5 0 0);
boundaryField
{
    inlet { type fixedValue; value uniform (5 0 0); }
    outlet { type mixed; refValue nonuniform List<vector> 40(%s); refGradient uniform (0 0 0);
             valueFraction uniform 0; value nonuniform List<vector> 40(%s); }
    obstacle { type slip; }
    ".*" { type symmetryPlane; }
    defaultFaces { type empty; }
}
""" % (outlet_U, outlet_U),
    "alpha": HEAD % ("volScalarField", "alpha") + """dimensions [0 0 0 0 0 0 0];
internalField uniform 0.5;
boundaryField { ".*" { type zeroGradient; } defaultFaces { type empty; } }
""",
}
for name, text in HAND_FIELDS.items():
    with open(os.path.join(HAND, "0", name), "w") as f:
        f.write(text)
case = os.path.join(OUT, "handwritten")
before = len(messages.GetOutput())
SaveData(os.path.join(case, "handwritten.foam"), proxy=reader, SourceCase=HAND, SourceTime="0")
text = messages.GetOutput()[before:]
check("ERROR" not in text and "no array 'alpha'" in text,
      "handwritten: written, with a warning that alpha (no input array) is written uniform %r" % text[-300:])
written = sorted(os.listdir(os.path.join(case, "0")))
check(written == ["T", "U", "alpha", "p"], "handwritten: the source's fields at 0 are written (not rho): %s" % written)
fields = {f: foamcase.read_field(os.path.join(case, "0", f)) for f in written}
_, _, _, _, boundary = foamcase.read_polymesh(case)
_, _, owner, neighbour, _ = foamcase.read_polymesh(case)
start = {name: (int(e["startFace"]), int(e["nFaces"])) for name, e in boundary}


def entry_type(f, patch):
    return re.search(r"type\s+(\w+);", fields[f][3][patch]).group(1)


check(re.search(r"value\s+uniform 1;", fields["p"][3]["inlet"]) is not None,
      "handwritten: p inlet's `value $internalField` becomes the source's uniform internalField")
check(entry_type("p", "outlet") == entry_type("p", "obstacle") == "zeroGradient",
      "handwritten: p's regular expression \"(outlet|obstacle)\" gives both patches zeroGradient")
check(entry_type("p", "bottom") == entry_type("p", "top") == "symmetryPlane",
      "handwritten: p's group entry symmetryPlane reaches bottom and top (inGroups)")
with open(os.path.join(case, "0", "T")) as f:
    t_text = f.read()
s0, n0 = start["outlet"]
t_out = foamcase.nonuniform_values(fields["T"][3]["outlet"])
check(re.search(r"^Tinlet 1;", t_text, re.M) is not None and "uniform $Tinlet" in fields["T"][3]["inlet"] and
      "inletValue uniform 1" in fields["T"][3]["outlet"] and t_out is not None and len(t_out) == n0 and
      np.array_equal(np.asarray(t_out, np.float32), np.asarray(fields["T"][2], np.float32)[owner[s0:s0 + n0]]),
      "handwritten: T keeps its macro Tinlet and inletOutlet entries; its value list is the outlet cells' values")
check(entry_type("T", "bottom") == "symmetryPlane" and entry_type("T", "defaultFaces") == "empty",
      "handwritten: T's \".*\" zeroGradient is overridden by the constraint types symmetryPlane and empty")
ref = re.search(r"refValue\s+uniform\s+\(([^)]*)\)", fields["U"][3]["outlet"])
mean = np.mean([1 + 0.1 * i for i in range(40)])
check(ref is not None and np.allclose([float(v) for v in ref.group(1).split()], [mean, 0, 0], rtol=1e-12),
      "handwritten: U outlet's nonuniform refValue becomes uniform at its mean (%s)" % (ref.group(1) if ref else None))
check(fields["alpha"][2] == "uniform 0.5" and entry_type("alpha", "inlet") == "zeroGradient",
      "handwritten: alpha (no input array) is written uniform 0.5, as the source's internalField")
ok = True
for f in written:
    rc, log = foamcase.run(BASHRC, case, "foamDictionary -expand 0/%s" % f)
    ok &= rc == 0
check(ok, "handwritten: OpenFOAM's foamDictionary reads and expands every written field")
for command in ("foamDictionary -entry deltaT -set 1e-05 system/controlDict",
                "foamDictionary -entry endTime -set 2e-05 system/controlDict",
                "foamDictionary -entry writeInterval -set 2e-05 system/controlDict"):
    foamcase.run(BASHRC, case, command)
rc, log = foamcase.run(BASHRC, case, "rhoCentralFoam")
check(rc == 0 and log.rstrip().endswith("End"), "handwritten: rhoCentralFoam runs 2 steps with these boundary conditions (exit %d)" % rc)
if rc != 0:
    artest.say(log[-1500:])


# ================================================ (c) bad source cases
def refused(label, fragment, source, **props):
    target = os.path.join(OUT, label)
    before = len(messages.GetOutput())
    SaveData(os.path.join(target, label + ".foam"), proxy=reader, SourceCase=source, **props)
    text = messages.GetOutput()[before:]
    check(fragment in text and "nothing is written" in text, "%s: error says %r" % (label, fragment))
    check(not [e for e in os.listdir(OUT) if label in e], "%s: nothing written" % label)


broken = os.path.join(OUT, "broken_source")
shutil.copytree(SRC, broken, ignore=shutil.ignore_patterns("0.00*", "log.*"))
path = os.path.join(broken, "constant", "polyMesh", "boundary")
with open(path) as f:
    text = f.read()
with open(path, "w") as f:
    f.write(text.replace("nFaces", "{ nFaces", 1))
refused("malformed", "is not a readable polyMesh boundary file", broken)
refused("notime", "has no time directory '7'", SRC, SourceTime="7")
artest.finish()
