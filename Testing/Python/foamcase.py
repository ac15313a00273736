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


def boundary_patches(text):
    """{name: nFaces} of the text of a constant/polyMesh/boundary file."""
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    text = re.sub(r"//[^\n]*", "", text)
    return {m.group(1): int(m.group(2))
            for m in re.finditer(r"(\w+)\s*\{[^{}]*?nFaces\s+(\d+);[^{}]*\}", text)}
