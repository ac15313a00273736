"""The OpenFOAM case writer's binary format (Format binary) against its
ASCII output, read by OpenFOAM itself.

Two inputs, each written twice (Format ascii, Format binary):
(a) Data/hybrid_wall.vtu (tetrahedra, prisms, hexahedra, pyramids), no
    SourceCase: its arrays become fields;
(b) OpenFOAM's rhoCentralFoam tutorial wedge15Ma5 after blockMesh and 20
    solver steps, read by ParaView's OpenFOAM reader and written with it as
    SourceCase: patch types from the source, nonuniform `value` lists on the
    patches (binary lists inside the boundaryField).
For each: the binary files' headers say `format binary` with `arch
"LSB;label=32;scalar=64"` and the faces are a faceCompactList; the binary
case is smaller; OpenFOAM's checkMesh says "Mesh OK." on it with the ASCII
case's cells per type; OpenFOAM's foamFormatConvert (writeFormat ascii,
writePrecision 17: every double read back exactly) turns a copy back into
ASCII, and that copy's points, faces, owner, neighbour and boundary, and
every field's class, dimensions, cell values, boundary types and nonuniform
lists, equal the ASCII case's: faces, owner, neighbour exactly, every
number either the same double, or, where the ASCII case has the shortest
text of a float (a value a float holds exactly, as the OpenFOAM reader's
are), the double of that float; ParaView's OpenFOAM reader reads the
binary case with the ASCII case's cells and cell arrays (exactly).
A Format that is neither 0 (ascii) nor 1 (binary) is refused with an error
naming Format, and nothing is written.
"""
import os
import re
import shutil

import numpy as np
from paraview.simple import *
from paraview import servermanager
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow

import artest
import foamcase
from artest import check

BASHRC = foamcase.bashrc("the OpenFOAM case writer's binary format")
TUTORIAL = foamcase.tutorial("compressible/rhoCentralFoam/wedge15Ma5")
artest.load_plugin(globals())
messages = vtkStringOutputWindow()
vtkOutputWindow.SetInstance(messages)
OUT = os.path.join(artest.OUTPUT_DIR, "FoamCaseWriterBinary")
shutil.rmtree(OUT, ignore_errors=True)
os.makedirs(OUT)
POLYMESH = ("points", "faces", "owner", "neighbour")


def same_numbers(ascii_values, converted):
    """Every converted value (binary, read back exactly) is the ASCII
    case's double, or the float whose shortest text the ASCII case has."""
    a = np.asarray(ascii_values, dtype=np.float64)
    c = np.asarray(converted, dtype=np.float64)
    if a.shape != c.shape:
        return False
    as_float = (c.astype(np.float32).astype(np.float64) == c) & (a.astype(np.float32) == c.astype(np.float32))
    return bool(np.all((a == c) | as_float))


def arch(path):
    with open(path, "rb") as f:
        m = re.search(r'arch\s+"([^"]*)"\s*;', f.read(8192).decode("latin-1"))
    return m.group(1) if m else None


def du(case):
    return sum(os.path.getsize(os.path.join(d, f)) for d, _, fs in os.walk(case) for f in fs)


def write(label, proxy, fmt, **props):
    case = os.path.join(OUT, "%s_%s" % (label, fmt))
    before = len(messages.GetOutput())
    SaveData(os.path.join(case, "case.foam"), proxy=proxy, Format=fmt, **props)
    text = messages.GetOutput()[before:]
    check(os.path.isfile(os.path.join(case, "constant", "polyMesh", "owner")) and "ERROR" not in text,
          "%s: written as %s, no error %r" % (label, fmt, text[-300:]))
    return case


def checkmesh(case, label):
    rc, log = foamcase.run(BASHRC, case, "checkMesh")
    ok = rc == 0 and "Mesh OK." in log and "Failed" not in log
    check(ok, "%s: checkMesh says 'Mesh OK.' (exit %d)" % (label, rc))
    if not ok:
        artest.say(log[log.find("Checking"):][-3000:])
    return {k: int(v) for k, v in re.findall(r"^\s+(hexahedra|prisms|pyramids|tetrahedra|polyhedra):\s+(\d+)",
                                              log, re.M)}


def fields_of(case):
    d = os.path.join(case, "0")
    return sorted(f for f in os.listdir(d) if os.path.isfile(os.path.join(d, f)))


def reader_arrays(case):
    """Cells and cell arrays of a case as ParaView's OpenFOAM reader gives them."""
    r = OpenFOAMReader(FileName=os.path.join(case, "case.foam"))
    r.SkipZeroTime = 0  # the fields are in 0/
    r.Refresh()
    r.UpdatePipelineInformation()
    r.MeshRegions = ["internalMesh"]
    r.CellArrays = r.CellArrays.Available
    r.UpdatePipeline(0.0)
    data = servermanager.Fetch(r)
    Delete(r)
    grid = data.GetBlock(0)
    cd = grid.GetCellData()
    arrays = {cd.GetArrayName(i): vtk_to_numpy(cd.GetArray(i)).copy() for i in range(cd.GetNumberOfArrays())}
    return grid.GetNumberOfCells(), vtk_to_numpy(grid.GetPoints().GetData()).copy(), arrays


def compare(label, ascii_case, binary_case):
    """The binary case against the ASCII one (see the module's text)."""
    for name in POLYMESH:
        h = foamcase.header(os.path.join(binary_case, "constant", "polyMesh", name))
        want = "faceCompactList" if name == "faces" else h.get("class")
        a = arch(os.path.join(binary_case, "constant", "polyMesh", name))
        check(h.get("format") == "binary" and a == "LSB;label=32;scalar=64" and h.get("class") == want,
              "%s: polyMesh/%s's header says format binary, arch LSB;label=32;scalar=64, class %s (%s)"
              % (label, name, want, h))
    for f in fields_of(binary_case):
        h = foamcase.header(os.path.join(binary_case, "0", f))
        check(h.get("format") == "binary", "%s: field %s's header says format binary" % (label, f))
    a_size, b_size = du(ascii_case), du(binary_case)
    check(b_size < a_size, "%s: the binary case is smaller (%d bytes, ASCII %d)" % (label, b_size, a_size))
    counts_a = checkmesh(ascii_case, label + " ascii")
    counts_b = checkmesh(binary_case, label + " binary")
    check(counts_a == counts_b and sum(counts_b.values()) > 0,
          "%s: checkMesh's cells per type on the binary case %s = the ASCII case's %s" % (label, counts_b, counts_a))

    # OpenFOAM reads the binary files and writes them as ASCII, every double exact.
    converted = binary_case + "_converted"
    shutil.copytree(binary_case, converted)
    for key, value in (("writeFormat", "ascii"), ("writePrecision", "17"), ("writeCompression", "off")):
        rc, log = foamcase.run(BASHRC, converted, "foamDictionary -entry %s -set %s system/controlDict" % (key, value))
        check(rc == 0, "%s: foamDictionary sets %s %s" % (label, key, value))
    rc, log = foamcase.run(BASHRC, converted, "foamFormatConvert")
    check(rc == 0 and "FOAM FATAL" not in log, "%s: foamFormatConvert reads the binary case (exit %d)" % (label, rc))
    if rc != 0:
        artest.say(log[-2000:])
    converted_header = foamcase.header(os.path.join(converted, "constant", "polyMesh", "faces"))
    check(converted_header.get("format") == "ascii", "%s: foamFormatConvert rewrote polyMesh/faces as ASCII" % label)
    pa, fa, oa, na, ba = foamcase.read_polymesh(ascii_case)
    pc, fc, oc, nc, bc = foamcase.read_polymesh(converted)
    check(same_numbers(pa, pc), "%s: %d points read back by OpenFOAM equal the ASCII case's" % (label, len(pa)))
    check(len(fa) == len(fc) and all(np.array_equal(x, y) for x, y in zip(fa, fc)),
          "%s: %d faces read back by OpenFOAM equal the ASCII case's (the same points, in order)" % (label, len(fa)))
    check(np.array_equal(oa, oc) and np.array_equal(na, nc),
          "%s: owner (%d) and neighbour (%d) read back equal the ASCII case's" % (label, len(oa), len(na)))
    strip = lambda b: [(n, {k: "".join(v.split()) for k, v in e.items()}) for n, e in b]
    check(strip(ba) == strip(bc), "%s: boundary read back equals the ASCII case's %s" % (label, [n for n, _ in ba]))
    names = fields_of(ascii_case)
    check(names == fields_of(converted) and names, "%s: the same fields %s" % (label, names))
    for f in names:
        cls_a, dims_a, int_a, patches_a = foamcase.read_field(os.path.join(ascii_case, "0", f))
        cls_c, dims_c, int_c, patches_c = foamcase.read_field(os.path.join(converted, "0", f))
        same_lists = True
        listed = 0
        for p, entry in patches_a.items():
            va = foamcase.nonuniform_values(entry)
            vc = foamcase.nonuniform_values(patches_c.get(p, ""))
            ta = re.search(r"type\s+(\w+);", entry)
            tc = re.search(r"type\s+(\w+);", patches_c.get(p, ""))
            same_lists &= (ta and tc and ta.group(1) == tc.group(1)) and \
                ((va is None and vc is None) or (va is not None and vc is not None and same_numbers(va, vc)))
            listed += va is not None
        check(cls_a == cls_c and dims_a.replace(" ", "") == dims_c.replace(" ", "") and isinstance(int_c, np.ndarray) and same_numbers(int_a, int_c),
              "%s: field %s read back by OpenFOAM: class %s, dimensions, %d cell values equal the ASCII case's"
              % (label, f, cls_c, len(int_c) if isinstance(int_c, np.ndarray) else -1))
        check(same_lists and set(patches_a) == set(patches_c),
              "%s: field %s's boundary types and %d nonuniform patch lists read back equal" % (label, f, listed))

    # ParaView's OpenFOAM reader on the binary case.
    na_, pa_, aa = reader_arrays(ascii_case)
    nb_, pb_, ab = reader_arrays(binary_case)
    check(na_ == nb_ and np.array_equal(pa_, pb_), "%s: the OpenFOAM reader reads %d cells and the same points from "
          "the binary case (ASCII %d)" % (label, nb_, na_))
    check(sorted(aa) == sorted(ab) and aa and all(np.array_equal(aa[k], ab[k]) for k in aa),
          "%s: the OpenFOAM reader's cell arrays %s equal on both cases" % (label, sorted(ab)))


# ---- (a) the hybrid mesh, no SourceCase.
hybrid = XMLUnstructuredGridReader(FileName=[artest.data("hybrid_wall.vtu")])
cases = {fmt: write("hybrid", hybrid, fmt) for fmt in ("ascii", "binary")}
compare("hybrid", cases["ascii"], cases["binary"])

# ---- (b) the wedge15Ma5 tutorial, solved, as SourceCase.
SRC = os.path.join(OUT, "source")
if not foamcase.solved_tutorial(BASHRC, TUTORIAL, SRC, "0.002", "0.002", check):
    artest.finish()
open(os.path.join(SRC, "source.foam"), "w").close()
reader = OpenFOAMReader(FileName=os.path.join(SRC, "source.foam"))
reader.MeshRegions = ["internalMesh"] + [r for r in reader.MeshRegions.Available if r.startswith("patch/")]
reader.CellArrays = reader.CellArrays.Available
scene = GetAnimationScene()
scene.UpdateAnimationUsingDataTimeSteps()
scene.AnimationTime = 0.002
reader.UpdatePipeline(0.002)
cases = {fmt: write("wedge", reader, fmt, SourceCase=SRC) for fmt in ("ascii", "binary")}
lists = sum(foamcase.nonuniform_values(e) is not None for f in fields_of(cases["ascii"])
            for e in foamcase.read_field(os.path.join(cases["ascii"], "0", f))[3].values())
check(lists > 0, "wedge: the ASCII case's fields have nonuniform patch value lists (%d)" % lists)
compare("wedge", cases["ascii"], cases["binary"])

# ---- A Format out of range: refused by name, nothing written.
bad = os.path.join(OUT, "badformat")
writer = CreateWriter(os.path.join(bad, "case.foam"), hybrid)
before = len(messages.GetOutput())
writer.Format = 2  # past the GUI's enumeration
writer.UpdatePipeline()
text = messages.GetOutput()[before:]
check("Format is 2" in text and "nothing is written" in text and not os.path.exists(bad),
      "Format 2: refused naming Format, nothing written (%r)" % text[-300:])
artest.finish()
