"""MPI test driver (run with pvpython): the OpenFOAM case writer under
`mpiexec -np 2 pvbatch` (issue 13: SaveData('case/name.foam') failed there
with "No matching writer found for extension: foam") writes the case the
serial run writes.

    pvpython RunMPIFoamCaseWriter.py <pvbatch> <mpiexec>

Splits Data/cone20Ma2p5.vtu into a 2-piece .pvtu (SplitIntoPieces.py) and
runs MPIFoamCaseWriterPipeline.py serially on the whole mesh and on 2 ranks
(the volume from the partitioned reader with one ghost level; the OpenFOAM
reader's multiblock with the cone's five patches, each rank holding half of
its cells and patch faces). For both cases, the 2-rank case against the
serial one, independently of the numbering (the pieces' points are numbered
rank by rank): the same points; the same cells (each as its points'
coordinates); every face between the same two cells (which owns it follows
the numbering), or of the same cell in the same patch; the boundary file's patches with the same names, types and face
counts; every field at time 0 with the same value in every cell; the
2-rank case passes checkMesh ("Mesh OK.") and foamcase.check_polymesh
(upper-triangular order, closed cells, orientation, positive volumes).
"""
import os
import shutil
import sys

import numpy as np

import artest
import foamcase
from artest import check

pvbatch, mpiexec = sys.argv[1], sys.argv[2]
pvpython = os.path.join(os.path.dirname(pvbatch), "pvpython")
here = os.path.dirname(os.path.abspath(__file__))
script = os.path.join(here, "MPIFoamCaseWriterPipeline.py")
BASHRC = foamcase.bashrc("the case writer's MPI test (checkMesh)")


def canonical(case):
    """The case independent of its numbering: points (a set of coordinate
    tuples), cells {key: index}, faces {face key: (its two cells' keys) or
    (owner key, patch name)}, the patches [(name, type, nFaces)], fields {name:
    {cell key: value}}. A key is the sorted tuple of coordinates."""
    points, faces, owner, neighbour, boundary = foamcase.read_polymesh(case)
    P = [tuple(p) for p in points]
    n_cells = int(max(owner.max(), neighbour.max() if len(neighbour) else 0)) + 1
    cell_points = [set() for _ in range(n_cells)]
    for f, ids in enumerate(faces):
        cell_points[owner[f]].update(ids.tolist())
        if f < len(neighbour):
            cell_points[neighbour[f]].update(ids.tolist())
    cell_key = [tuple(sorted(P[i] for i in c)) for c in cell_points]
    patch_of = {}
    for name, e in boundary:
        for f in range(int(e["startFace"]), int(e["startFace"]) + int(e["nFaces"])):
            patch_of[f] = name
    face_map = {}
    for f, ids in enumerate(faces):
        key = tuple(sorted(P[i] for i in ids))
        # internal faces: the two cells, whichever owns (the numbering decides
        # it, and the orientation with it; check_polymesh checks that)
        face_map[key] = tuple(sorted((cell_key[owner[f]], cell_key[neighbour[f]]))) if f < len(neighbour) \
            else (cell_key[owner[f]], patch_of[f])
    fields = {}
    for name in sorted(os.listdir(os.path.join(case, "0"))):
        cls, dims, internal, patches = foamcase.read_field(os.path.join(case, "0", name))
        values = internal if isinstance(internal, str) else {cell_key[c]: tuple(np.atleast_1d(internal[c]))
                                                             for c in range(n_cells)}
        fields[name] = (cls, dims, values, sorted(patches))
    patches = [(name, e.get("type"), int(e["nFaces"])) for name, e in boundary]
    return set(P), len(points), cell_key, face_map, patches, fields


out = artest.OUTPUT_DIR
pieces = os.path.join(out, "mpifoam_pieces.pvtu")
whole = os.path.join(out, "mpifoam_whole.vtu")
serial, parallel = os.path.join(out, "mpifoam_serial"), os.path.join(out, "mpifoam_np2")
for d in (serial, parallel):
    shutil.rmtree(d, ignore_errors=True)
    os.makedirs(d)
rc, _ = artest.run([pvpython, os.path.join(here, "SplitIntoPieces.py"), artest.data("cone20Ma2p5.vtu"), pieces, whole])
check(rc == 0 and os.path.exists(pieces), "split into a 2-piece .pvtu")
rc, _ = artest.run([pvbatch, script, whole, serial])
check(rc == 0, "serial pvbatch run")
rc, text = artest.run([mpiexec, "--allow-run-as-root", "--oversubscribe", "-np", "2", pvbatch, "--symmetric",
                       script, pieces, parallel])
check(rc == 0 and "No matching writer" not in text and "ERR|" not in text, "mpiexec -np 2 pvbatch run, no error")

for label in ("volume", "patches"):
    s_case, p_case = os.path.join(serial, label), os.path.join(parallel, label)
    if not (os.path.exists(os.path.join(s_case, "constant", "polyMesh", "owner"))
            and os.path.exists(os.path.join(p_case, "constant", "polyMesh", "owner"))):
        check(False, "%s: both cases written" % label)
        continue
    check(os.path.exists(os.path.join(p_case, label + ".foam")), "%s: 2 ranks wrote %s/%s.foam" % (label, p_case, label))
    S, Q = canonical(s_case), canonical(p_case)
    check(S[0] == Q[0] and S[1] == Q[1], "%s: the same %d points (2 ranks %d)" % (label, S[1], Q[1]))
    check(sorted(S[2]) == sorted(Q[2]), "%s: the same %d cells (2 ranks %d)" % (label, len(S[2]), len(Q[2])))
    check(S[3] == Q[3], "%s: every one of the %d faces between the same cells or in the same patch (2 ranks %d faces)"
          % (label, len(S[3]), len(Q[3])))
    check(S[4] == Q[4], "%s: the same patches, types and face counts %s" % (label, Q[4]))
    same = {n: S[5][n] == Q[5].get(n) for n in S[5]}
    check(sorted(S[5]) == sorted(Q[5]) and all(same.values()) and len(S[5]) >= 4,
          "%s: the same fields at time 0, cell for cell, with the same patch entries (%s)"
          % (label, ", ".join("%s %s" % (n, "equal" if v else "DIFFERENT") for n, v in same.items())))
    rc, log = foamcase.run(BASHRC, p_case, "checkMesh")
    check(rc == 0 and "Mesh OK." in log, "%s: checkMesh says 'Mesh OK.' on the 2-rank case (exit %d)" % (label, rc))
    foamcase.check_polymesh(p_case, check, label + ", 2 ranks")

artest.finish()
