#!/usr/bin/env python3
"""Oblique-shock relations for a calorically perfect gas.

Importable module and small command-line tool (plain Python 3, ``math`` only).

theta-beta-Mach relation for a straight attached oblique shock that turns a
uniform supersonic stream of Mach number M by the wedge (deflection) angle
theta::

    tan(theta) = 2 cot(beta) (M^2 sin^2(beta) - 1) / (M^2 (gamma + cos 2 beta) + 2)

For 0 < theta < theta_max(M) there are two solutions: the *weak* one with
mu < beta < beta_max (mu = asin(1/M) is the Mach angle, beta_max the shock
angle of maximum deflection) and the *strong* one with beta_max < beta < 90
degrees.  Each is found by bisection on its own bracket, where the deflection
is monotonic, so the root is always the requested branch.

Functions
---------
shock_angle(mach, theta_deg, gamma=1.4, strong=False) -> beta in degrees
deflection_angle(mach, beta_deg, gamma=1.4)           -> theta in degrees
max_deflection(mach, gamma=1.4)                       -> (theta_max, beta_max), degrees
mach_angle(mach)                                      -> mu in degrees
oblique_shock_jump(mach, beta_deg, gamma=1.4)         -> ShockJump(p2_p1, rho2_rho1, T2_T1, M2)
    (Rankine-Hugoniot jumps across the shock; a named tuple, so it unpacks
    as ``p21, r21, T21, M2 = oblique_shock_jump(...)``)

Command line::

    python3 Data/theta_beta_mach.py MACH THETA_DEG [--gamma G] [--strong] [--verbose]

prints the shock angle beta in degrees (weak solution unless --strong);
--verbose also prints the jump ratios and the downstream Mach number.

Example: ``python3 Data/theta_beta_mach.py 5 15`` prints about 24.32.
"""

import argparse
import math
import sys
from collections import namedtuple

__all__ = [
    "shock_angle",
    "deflection_angle",
    "max_deflection",
    "mach_angle",
    "oblique_shock_jump",
    "ShockJump",
]

ShockJump = namedtuple("ShockJump", ["p2_p1", "rho2_rho1", "T2_T1", "M2"])


def _check(mach, gamma):
    if not (gamma > 1.0):
        raise ValueError("gamma must be > 1, got %r" % (gamma,))
    if not (mach > 1.0):
        raise ValueError("an oblique shock needs a supersonic upstream Mach number, got %r" % (mach,))


def mach_angle(mach):
    """Mach angle mu = asin(1/M) in degrees (M > 1)."""
    if not (mach > 1.0):
        raise ValueError("Mach angle needs M > 1, got %r" % (mach,))
    return math.degrees(math.asin(1.0 / mach))


def _tan_theta(mach, beta, gamma):
    """Right-hand side of the theta-beta-M relation; beta in radians."""
    m2 = mach * mach
    s = math.sin(beta)
    num = 2.0 * (m2 * s * s - 1.0) * math.cos(beta) / s
    den = m2 * (gamma + math.cos(2.0 * beta)) + 2.0
    return num / den


def deflection_angle(mach, beta_deg, gamma=1.4):
    """Flow deflection theta (degrees) produced by a shock of angle beta (degrees)."""
    _check(mach, gamma)
    return math.degrees(math.atan(_tan_theta(mach, math.radians(beta_deg), gamma)))


def max_deflection(mach, gamma=1.4):
    """(theta_max, beta_max) in degrees: the largest deflection an attached shock can make.

    beta_max is closed form (Anderson, Modern Compressible Flow, Eq. 4.17 solved
    for d(theta)/d(beta) = 0):
        sin^2 beta_max = [ (g+1)M^2/4 - 1
                           + sqrt((g+1)(1 + (g-1)M^2/2 + (g+1)M^4/16)) ] / (g M^2)
    """
    _check(mach, gamma)
    g = gamma
    m2 = mach * mach
    s2 = ((g + 1.0) * m2 / 4.0 - 1.0
          + math.sqrt((g + 1.0) * (1.0 + 0.5 * (g - 1.0) * m2 + (g + 1.0) * m2 * m2 / 16.0))) / (g * m2)
    s2 = min(max(s2, 0.0), 1.0)
    beta_max = math.asin(math.sqrt(s2))
    theta_max = math.atan(_tan_theta(mach, beta_max, gamma))
    return math.degrees(theta_max), math.degrees(beta_max)


def _bisect(f, a, b, tol=1e-14, maxiter=200):
    fa, fb = f(a), f(b)
    if fa == 0.0:
        return a
    if fb == 0.0:
        return b
    if fa * fb > 0.0:
        raise ValueError("root not bracketed")
    for _ in range(maxiter):
        m = 0.5 * (a + b)
        fm = f(m)
        if fm == 0.0 or (b - a) < tol:
            return m
        if fa * fm < 0.0:
            b, fb = m, fm
        else:
            a, fa = m, fm
    return 0.5 * (a + b)


def shock_angle(mach, theta_deg, gamma=1.4, strong=False):
    """Oblique shock angle beta (degrees) for upstream Mach `mach` and wedge angle `theta_deg`.

    Weak solution by default (the one seen on a sharp wedge), strong if
    ``strong=True``.  The root is bracketed between the Mach angle and
    beta_max (weak) or between beta_max and 90 degrees (strong), where
    theta(beta) is monotonic, and found by bisection to ~1e-12 degrees.

    theta = 0 gives the Mach wave (weak) or the normal shock (strong).
    Raises ValueError for M <= 1, theta < 0 or theta > theta_max (detached shock).
    """
    _check(mach, gamma)
    if theta_deg < 0.0:
        raise ValueError("wedge angle must be >= 0, got %r" % (theta_deg,))
    theta_max, beta_max = max_deflection(mach, gamma)
    if theta_deg > theta_max:
        raise ValueError(
            "theta = %g deg exceeds the maximum deflection %.6g deg at M = %g, gamma = %g: "
            "the shock detaches" % (theta_deg, theta_max, mach, gamma))
    mu = math.radians(mach_angle(mach))
    bmax = math.radians(beta_max)
    if theta_deg == 0.0:
        return 90.0 if strong else math.degrees(mu)
    if theta_deg == theta_max:
        return beta_max
    tt = math.tan(math.radians(theta_deg))

    def f(beta):
        return _tan_theta(mach, beta, gamma) - tt

    if strong:
        a, b = bmax, 0.5 * math.pi
    else:
        a, b = mu, bmax
    return math.degrees(_bisect(f, a, b))


def oblique_shock_jump(mach, beta_deg, gamma=1.4):
    """Rankine-Hugoniot jumps across an oblique shock of angle beta (degrees).

    Returns ShockJump(p2_p1, rho2_rho1, T2_T1, M2): static pressure, density
    and temperature ratios and the downstream Mach number.  The normal
    component Mn1 = M sin(beta) must be >= 1.
    """
    _check(mach, gamma)
    g = gamma
    beta = math.radians(beta_deg)
    mn1 = mach * math.sin(beta)
    if mn1 < 1.0 - 1e-12:
        raise ValueError("normal Mach number M sin(beta) = %g < 1: no shock" % mn1)
    mn1s = mn1 * mn1
    p21 = 1.0 + 2.0 * g / (g + 1.0) * (mn1s - 1.0)
    r21 = (g + 1.0) * mn1s / ((g - 1.0) * mn1s + 2.0)
    t21 = p21 / r21
    mn2 = math.sqrt((1.0 + 0.5 * (g - 1.0) * mn1s) / (g * mn1s - 0.5 * (g - 1.0)))
    theta = math.atan(_tan_theta(mach, beta, gamma))
    m2 = mn2 / math.sin(beta - theta)
    return ShockJump(p21, r21, t21, m2)


def main(argv=None):
    ap = argparse.ArgumentParser(
        description="Oblique shock angle from the theta-beta-Mach relation (prints beta in degrees).")
    ap.add_argument("mach", type=float, help="upstream Mach number (> 1)")
    ap.add_argument("theta", type=float, help="wedge / deflection angle in degrees")
    ap.add_argument("--gamma", type=float, default=1.4, help="ratio of specific heats (default 1.4)")
    ap.add_argument("--strong", action="store_true", help="strong-shock solution instead of weak")
    ap.add_argument("-v", "--verbose", action="store_true", help="also print the jump conditions")
    a = ap.parse_args(argv)
    try:
        beta = shock_angle(a.mach, a.theta, a.gamma, a.strong)
    except ValueError as e:
        print("error: %s" % e, file=sys.stderr)
        return 1
    print("%.6f" % beta)
    if a.verbose:
        tmax, bmax = max_deflection(a.mach, a.gamma)
        j = oblique_shock_jump(a.mach, beta, a.gamma)
        print("mach_angle %.6f" % mach_angle(a.mach))
        print("theta_max %.6f beta_max %.6f" % (tmax, bmax))
        print("p2/p1 %.6f rho2/rho1 %.6f T2/T1 %.6f M2 %.6f" % j)
    return 0


if __name__ == "__main__":
    sys.exit(main())
