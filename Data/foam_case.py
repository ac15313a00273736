"""Reading an OpenFOAM case's dictionaries (plain python3: re, os).

Shared by the converters of the OpenFOAM datasets (convert_wedge15Ma5.py,
convert_cone20Ma2p5.py): comments stripped, nested `key { ... }` and
`key ( ... )` blocks, scalars, `value uniform ...` entries, the gas
properties (constant Cp, perfect gas) and the fixedValue inlet state.
"""
import os
import re

UNIVERSAL_R = 8314.47  # J/(kmol K), OpenFOAM's constant::thermodynamics::RR


# ---------------------------------------------------------------- OpenFOAM dictionary helpers
def read_dict(path):
    with open(path) as f:
        txt = f.read()
    txt = re.sub(r"/\*.*?\*/", " ", txt, flags=re.S)
    txt = re.sub(r"//[^\n]*", " ", txt)
    return txt


def enclosed(txt, start, open_ch, close_ch):
    """Text between the bracket at txt[start] and its matching closing bracket."""
    assert txt[start] == open_ch
    depth = 0
    for i in range(start, len(txt)):
        if txt[i] == open_ch:
            depth += 1
        elif txt[i] == close_ch:
            depth -= 1
            if depth == 0:
                return txt[start + 1:i]
    raise ValueError("unbalanced %s%s" % (open_ch, close_ch))


def sub(txt, key, kind="{"):
    """Contents of `key { ... }` (kind '{') or `key ( ... )` (kind '(')."""
    close = "}" if kind == "{" else ")"
    m = re.search(r"(?<![\w.])%s\s*\%s" % (re.escape(key), kind), txt)
    if not m:
        raise KeyError(key)
    return enclosed(txt, m.end() - 1, kind, close)


def scalar(txt, key):
    m = re.search(r"(?<![\w.])%s\s+([-+0-9.eE]+)\s*;" % re.escape(key), txt)
    if not m:
        raise KeyError(key)
    return float(m.group(1))


def uniform_value(txt):
    """Value of `value uniform X;` with X a scalar or a (vector)."""
    m = re.search(r"\bvalue\s+uniform\s+(\([^)]*\)|[-+0-9.eE]+)\s*;", txt)
    if not m:
        raise KeyError("value uniform")
    v = m.group(1).strip("()").split()
    return [float(x) for x in v]


# ---------------------------------------------------------------- case metadata
def gas_properties(case):
    tp = read_dict(os.path.join(case, "constant", "thermophysicalProperties"))
    thermo_type = sub(tp, "thermoType")
    for key, want in (("thermo", "hConst"), ("equationOfState", "perfectGas")):
        m = re.search(r"\b%s\s+(\w+)\s*;" % key, thermo_type)
        if not m or m.group(1) != want:
            raise RuntimeError("expected %s %s in thermoType (constant gamma), got %s"
                               % (key, want, m.group(1) if m else None))
    mixture = sub(tp, "mixture")
    mol_weight = scalar(sub(mixture, "specie"), "molWeight")
    cp = scalar(sub(mixture, "thermodynamics"), "Cp")
    r_gas = UNIVERSAL_R / mol_weight
    gamma = cp / (cp - r_gas)
    return gamma, r_gas, cp, mol_weight


def inlet_state(case, time_dir):
    """(U vector, T, p) of the fixedValue inlet patch, from the time directory read."""
    vals = {}
    for name in ("U", "T", "p"):
        path = os.path.join(case, time_dir, name)
        if not os.path.exists(path):
            path = os.path.join(case, "0", name)
        txt = read_dict(path)
        inlet = sub(sub(txt, "boundaryField"), "inlet")
        if not re.search(r"\btype\s+fixedValue\s*;", inlet):
            raise RuntimeError("%s: inlet is not fixedValue" % path)
        vals[name] = uniform_value(inlet)
    return vals["U"], vals["T"][0], vals["p"][0]
