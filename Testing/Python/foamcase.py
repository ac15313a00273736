"""OpenFOAM from the tests: find its bashrc and its tutorials (a test fails,
naming the package, where they are missing: the README's set-up installs
both), lay out a minimal case, run a utility in it, read polyMesh/boundary.

AR_OPENFOAM_BASHRC overrides where the bashrc is looked for.
"""
import glob
import os
import re
import subprocess
import sys

import artest

HEADER = "FoamFile { version 2.0; format ascii; class dictionary; object %s; }\n"
CASE_FILES = {
    "system/controlDict": HEADER % "controlDict" +
    "application none;\nstartFrom startTime;\nstartTime 0;\nstopAt endTime;\nendTime 1;\n"
    "deltaT 1;\nwriteControl timeStep;\nwriteInterval 1;\n",
    "system/fvSchemes": HEADER % "fvSchemes" +
    "ddtSchemes { default none; }\ngradSchemes { default Gauss linear; }\ndivSchemes { default none; }\n"
    "laplacianSchemes { default none; }\ninterpolationSchemes { default linear; }\n"
    "snGradSchemes { default corrected; }\n",
    "system/fvSolution": HEADER % "fvSolution",
}


TUTORIALS = "/usr/share/doc/openfoam-examples/examples"


def bashrc(what):
    """OpenFOAM's bashrc. Where there is none the test fails (exit 1) with
    the package to install. `what`: what needs OpenFOAM."""
    candidates = ["/usr/share/openfoam/etc/bashrc"] + sorted(glob.glob("/usr/lib/openfoam/*/etc/bashrc"))
    if os.environ.get("AR_OPENFOAM_BASHRC"):
        candidates = [os.environ["AR_OPENFOAM_BASHRC"]]
    found = next((b for b in candidates if os.path.exists(b)), None)
    if found is None:
        artest.say("FAIL OpenFOAM is not installed (none of %s), and %s needs it: apt-get install openfoam "
                   "(the README's set-up command installs it)" % (candidates, what))
        sys.exit(1)
    return found


def tutorial(relative):
    """The directory of one of OpenFOAM's tutorials (package openfoam-examples),
    e.g. "compressible/rhoCentralFoam/wedge15Ma5"; the test fails (exit 1)
    naming the package where it is missing."""
    path = os.path.join(TUTORIALS, relative)
    if not os.path.isdir(path):
        artest.say("FAIL OpenFOAM's tutorial %s is not installed: apt-get install openfoam-examples "
                   "(the README's set-up command installs it)" % path)
        sys.exit(1)
    return path


def make_case(case):
    """The system/ files a utility needs, under `case`."""
    for rel, text in CASE_FILES.items():
        os.makedirs(os.path.dirname(os.path.join(case, rel)), exist_ok=True)
        with open(os.path.join(case, rel), "w") as f:
            f.write(text)


def run(bashrc, case, command):
    """Runs an OpenFOAM utility in `case` (bashrc sourced in bash -c); its
    output also goes to case/log.<utility>. Returns (exit code, output)."""
    r = subprocess.run(["bash", "-c", "source '%s' >/dev/null 2>&1; cd '%s' && %s" % (bashrc, case, command)],
                       env=artest.child_environment(), stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       text=True, timeout=120)
    with open(os.path.join(case, "log." + command.split()[0]), "w") as f:
        f.write(r.stdout)
    return r.returncode, r.stdout


def solved_tutorial(bashrc, tutorial, case, end_time, write_interval, check):
    """A copy of an OpenFOAM tutorial in `case` (writable, its .gz files
    unpacked), meshed with blockMesh and run with rhoCentralFoam to
    `end_time`, writing every `write_interval`; each step asserted with
    `check`. Returns False (after printing the log's end) when a step failed."""
    import gzip
    import shutil
    shutil.copytree(tutorial, case)
    for root, _, files in os.walk(case):
        os.chmod(root, 0o755)
        for f in files:
            os.chmod(os.path.join(root, f), 0o644)
            if f.endswith(".gz"):
                with gzip.open(os.path.join(root, f)) as z, open(os.path.join(root, f[:-3]), "wb") as o:
                    o.write(z.read())
                os.remove(os.path.join(root, f))
    for command in ("foamDictionary -entry endTime -set %s system/controlDict" % end_time,
                    "foamDictionary -entry writeInterval -set %s system/controlDict" % write_interval,
                    "blockMesh", "rhoCentralFoam"):
        rc, log = run(bashrc, case, command)
        check(rc == 0, "source case: %s exits 0" % command)
        if rc != 0:
            artest.say(log[-2000:])
            return False
    return True


def boundary_patches(text):
    """{name: nFaces} of the text of a constant/polyMesh/boundary file."""
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    text = re.sub(r"//[^\n]*", "", text)
    return {m.group(1): int(m.group(2))
            for m in re.finditer(r"(\w+)\s*\{[^{}]*?nFaces\s+(\d+);[^{}]*\}", text)}


def patch_types(case):
    """{name: type} of the case's constant/polyMesh/boundary."""
    text = open(os.path.join(case, "constant", "polyMesh", "boundary")).read()
    return {m.group(1): m.group(2) for m in re.finditer(r"^\s*(\w+)\s*\{[^}]*?\btype\s+(\w+);", text, re.M | re.S)}


# ---------------------------------------------------------------- reading a written case (numpy)
def _strip(text):
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    return re.sub(r"//[^\n]*", " ", text)


def _body(text):
    """The text after the FoamFile header."""
    text = _strip(text)
    m = re.search(r"FoamFile\s*\{", text)
    if not m:
        raise ValueError("no FoamFile header")
    return text[_close(text, m.end() - 1) + 1:]


def _close(text, start):
    """Index of the bracket closing text[start]."""
    pairs = {"(": ")", "{": "}", "[": "]"}
    depth = 0
    for i in range(start, len(text)):
        if text[i] in pairs:
            depth += 1
        elif text[i] in pairs.values():
            depth -= 1
            if depth == 0:
                return i
    raise ValueError("unbalanced brackets")


def header(path):
    """{key: value} of a file's FoamFile header (the file's start only, as
    bytes: a binary file's raw lists are not text)."""
    with open(path, "rb") as f:
        text = _strip(f.read(8192).decode("latin-1"))
    m = re.search(r"FoamFile\s*\{", text)
    inner = text[m.end():_close(text, m.end() - 1)]
    return {k: v.strip().strip('"') for k, v in re.findall(r"(\w+)\s+([^;]*);", inner)}


def _list(text):
    """The inside of the first `N ( ... )` list of `text` and N."""
    m = re.search(r"(\d+)\s*\(", text)
    end = _close(text, m.end() - 1)
    return int(m.group(1)), text[m.end():end]


def read_polymesh(case):
    """points (n, 3), faces [array of ids], owner, neighbour, boundary
    [(name, {entries})] of case/constant/polyMesh, parsed here."""
    d = os.path.join(case, "constant", "polyMesh")
    with open(os.path.join(d, "points")) as f:
        n, inner = _list(_body(f.read()))
    points = np.array(inner.replace("(", " ").replace(")", " ").split(), dtype=float).reshape(-1, 3)
    assert len(points) == n, "points: count"
    with open(os.path.join(d, "faces")) as f:
        n, inner = _list(_body(f.read()))
    faces = [np.array(ids.split(), dtype=np.int64) for _, ids in re.findall(r"(\d+)\s*\(([^()]*)\)", inner)]
    assert len(faces) == n and all(len(f) == int(k) for f, (k, _) in zip(faces, re.findall(r"(\d+)\s*\(([^()]*)\)", inner))), "faces: counts"
    lists = []
    for name in ("owner", "neighbour"):
        with open(os.path.join(d, name)) as f:
            n, inner = _list(_body(f.read()))
        lists.append(np.array(inner.split(), dtype=np.int64))
        assert len(lists[-1]) == n, name + ": count"
    with open(os.path.join(d, "boundary")) as f:
        n, inner = _list(_body(f.read()))
    boundary = []
    for m in re.finditer(r"(\S+)\s*\{", inner):
        if boundary and m.start() < boundary[-1][2]:
            continue
        end = _close(inner, m.end() - 1)
        body = inner[m.end():end]
        entries = {k: v.strip() for k, v in re.findall(r"(\w+)\s+([^;]*);", body)}
        boundary.append((m.group(1), entries, end))
    assert len(boundary) == n, "boundary: count"
    return points, faces, lists[0], lists[1], [(b[0], b[1]) for b in boundary]


import numpy as np  # noqa: E402  (the helpers above need it only when called)


def _area_vectors(points, faces):
    """Area vectors (right-hand normal, fan triangles from the face centre)
    and centres of the faces."""
    areas = np.zeros((len(faces), 3))
    centres = np.zeros((len(faces), 3))
    for k in (3, 4):
        idx = [i for i, f in enumerate(faces) if len(f) == k]
        if not idx:
            continue
        x = points[np.array([faces[i] for i in idx])]          # (m, k, 3)
        c = x.mean(axis=1)
        a = np.zeros((len(idx), 3))
        for j in range(k):
            a += 0.5 * np.cross(x[:, j] - c, x[:, (j + 1) % k] - c)
        areas[idx] = a
        centres[idx] = c
    return areas, centres


def check_polymesh(case, check, label):
    """Checks the written polyMesh of `case` independently of checkMesh:
    owner < neighbour and internal faces sorted by (owner, neighbour)
    (upper-triangular order); patches contiguous after the internal faces
    and covering every face; every cell closed (its outward area vectors sum
    to ~0); every face pointing from its owner to its neighbour / out of the
    domain (area vector . (face centre - owner centre) > 0, and < 0 towards
    the neighbour); every cell volume (divergence theorem) positive. Returns
    (points, faces, owner, neighbour, boundary, cell volumes, cell centres)."""
    points, faces, owner, neighbour, boundary = read_polymesh(case)
    n_internal = len(neighbour)
    n_cells = int(max(owner.max(), neighbour.max() if n_internal else 0)) + 1
    check(np.all(owner[:n_internal] < neighbour), "%s: owner < neighbour on every internal face" % label)
    key = owner[:n_internal] * (n_cells + 1) + neighbour
    check(np.all(np.diff(key) >= 0), "%s: internal faces in upper-triangular order (sorted by owner, then neighbour)" % label)
    start = n_internal
    contiguous = True
    for name, e in boundary:
        contiguous &= int(e["startFace"]) == start
        start += int(e["nFaces"])
    check(contiguous and start == len(faces) == len(owner),
          "%s: %d patches contiguous after the %d internal faces, %d faces in all" % (label, len(boundary), n_internal, start))
    areas, centres = _area_vectors(points, faces)
    # Cell centres: mean of the cells' face centres (enough for a sidedness test of convex cells).
    count = np.bincount(owner, minlength=n_cells) + np.bincount(neighbour, minlength=n_cells)
    cc = np.zeros((n_cells, 3))
    for k in range(3):
        cc[:, k] = (np.bincount(owner, centres[:, k], n_cells) + np.bincount(neighbour, centres[:n_internal, k], n_cells)) / count
    closure = np.zeros((n_cells, 3))
    for k in range(3):
        closure[:, k] = np.bincount(owner, areas[:, k], n_cells) - np.bincount(neighbour, areas[:n_internal, k], n_cells)
    magnitude = np.linalg.norm(areas, axis=1)
    scale = np.bincount(owner, magnitude, n_cells) + np.bincount(neighbour, magnitude[:n_internal], n_cells)
    check(np.all(np.linalg.norm(closure, axis=1) <= 1e-9 * scale),
          "%s: every cell closed (its outward face area vectors sum to 0)" % label)
    out_owner = np.einsum("ij,ij->i", areas, centres - cc[owner])
    out_neigh = np.einsum("ij,ij->i", areas[:n_internal], centres[:n_internal] - cc[neighbour])
    check(np.all(out_owner > 0) and np.all(out_neigh < 0),
          "%s: every face points from its owner to its neighbour / out of the domain (%d wrong)"
          % (label, int((out_owner <= 0).sum() + (out_neigh >= 0).sum())))
    flux = np.einsum("ij,ij->i", areas, centres) / 3.0
    volume = np.bincount(owner, flux, n_cells) - np.bincount(neighbour, flux[:n_internal], n_cells)
    check(np.all(volume > 0), "%s: every cell volume positive (min %.3g)" % (label, volume.min()))
    return points, faces, owner, neighbour, boundary, volume, cc


def read_field(path):
    """(class, dimensions text, internal values (n,) / (n, 3) or the uniform
    text, {patch: entry text}) of a field file."""
    with open(path) as f:
        text = _body(f.read())
    cls = header(path)["class"]
    dims = re.search(r"dimensions\s+(\[[^\]]*\])\s*;", text).group(1)
    m = re.search(r"internalField\s+", text)
    rest = text[m.end():]
    if rest.startswith("uniform"):
        internal = rest[:rest.index(";")].strip()
    else:
        n, inner = _list(rest)
        internal = np.array(inner.replace("(", " ").replace(")", " ").split(), dtype=float)
        internal = internal.reshape(n, -1) if cls == "volVectorField" else internal
        assert len(internal) == n, "internalField: count"
    m = re.search(r"boundaryField\s*\{", text)
    inner = text[m.end():_close(text, m.end() - 1)]
    patches = {}
    i = 0
    for m in re.finditer(r"(\S+)\s*\{", inner):
        if m.start() < i:
            continue
        end = _close(inner, m.end() - 1)
        patches[m.group(1)] = inner[m.end():end]
        i = end
    return cls, " ".join(dims.split()), internal, patches


def nonuniform_values(entry, key="value"):
    """The values of `key nonuniform List<...> n (...)` in a patch entry, or None."""
    m = re.search(r"\b%s\s+nonuniform\s+List<(\w+)>\s*(\d+)\s*\(" % key, entry)
    if not m:
        return None
    inner = entry[m.end():_close(entry, m.end() - 1)]
    v = np.array(inner.replace("(", " ").replace(")", " ").split(), dtype=float)
    return v.reshape(int(m.group(2)), -1) if m.group(1) == "vector" else v
