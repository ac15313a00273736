#!/usr/bin/env python3
"""Taylor-Maccoll solution: supersonic flow past a sharp cone at zero incidence.

Importable module and small command-line tool (plain Python 3, ``math`` only).

A uniform stream of Mach number M meets a sharp cone of half-angle theta_c.
If the shock stays attached it is a straight conical shock of half-angle beta
(measured from the cone axis), and between shock and cone the flow is conical
(it depends only on the polar angle theta from the axis) and isentropic.  With
the velocity scaled by the maximum speed, V' = V / V_max, and
V'_theta = dV'_r / dtheta (irrotational flow), the Taylor-Maccoll equation is

    (g-1)/2 (1 - V_r^2 - V_t^2) (2 V_r + V_t cot(theta) + V_r'')
        - V_t^2 (V_r + V_r'') = 0,           V_t = V_r'

(Anderson, Modern Compressible Flow, Ch. 10).  Solved for V_r'':

    V_r'' = [V_t^2 V_r - A (2 V_r + V_t cot theta)] / (A - V_t^2),
    A = (g-1)/2 (1 - V_r^2 - V_t^2).

Method (the classic inverse approach, as in Anderson):
  1. pick a shock angle beta; the oblique-shock relations give the deflection
     delta and the Mach number M2 just behind the shock; there
         V' = [2 / ((g-1) M2^2) + 1]^(-1/2),
         V_r = V' cos(beta - delta),   V_t = -V' sin(beta - delta);
  2. integrate the ODE with classic RK4 from theta = beta inward (decreasing
     theta, fixed step, default 1e-4 rad, refined to the exact zero) until
     V_t = 0: that theta is the cone half-angle theta_c(beta);
  3. bisect on beta in (mu, beta*) to match the requested cone angle, where
     mu = asin(1/M) is the Mach angle (theta_c -> 0) and beta* is found by a
     scan as the first beta with theta_c(beta) >= target (theta_c grows
     monotonically with beta on the weak, attached branch).

Functions
---------
cone_shock_angle(mach, cone_half_angle_deg, gamma=1.4)  -> beta in degrees
cone_angle(mach, shock_angle_deg, gamma=1.4)            -> theta_c in degrees
taylor_maccoll(mach, cone_half_angle_deg, gamma=1.4)    -> ConeSolution (named tuple):
    shock_angle      beta in degrees
    cone_angle       theta_c in degrees (echo of the input)
    cone_mach        Mach number on the cone surface
    cone_p_p1        static pressure on the cone / free-stream pressure
    cone_rho_rho1    density on the cone / free-stream density
    cone_T_T1        temperature on the cone / free-stream temperature
    shock_p2_p1      static-pressure jump across the shock (just behind it)
    shock_rho2_rho1  density jump across the shock
    shock_M2         Mach number just behind the shock
    deflection       flow deflection at the shock, delta in degrees
conical_profile(mach, cone_half_angle_deg, gamma=1.4, n=50)
    -> list of (theta_deg, p/p1, rho/rho1, T/T1, Mach, ux/V1, ur/V1) from the shock to the
       cone (ux along the axis, ur radial, both scaled by the free-stream speed V1)

Command line::

    python3 Data/taylor_maccoll.py MACH CONE_HALF_ANGLE_DEG [--gamma G] [--verbose] [--check]

prints the shock angle in degrees; --verbose also prints the cone-surface
values; --check runs the built-in comparisons with published values.

Checks (--check): M = 2, 20 deg cone -> beta = 37.8 deg (the textbook value,
e.g. the cone charts of NACA Report 1135); a 2 deg cone at M = 2.5 has the
surface pressure of slender-body theory within a few per cent; a 0.5 deg cone
carries (almost) the Mach wave; cone_angle inverts cone_shock_angle; halving
the RK4 step changes beta by < 1e-6 deg.

Values (gamma = 1.4):
    M = 2.0, 20 deg: beta = 37.796 deg, cone Mach 1.568, p_c/p1 = 1.912
    M = 2.5, 20 deg: beta = 32.581 deg, cone Mach 1.945, p_c/p1 = 2.309
                     (p2/p1 = 1.948 just behind the shock)
"""

import argparse
import math
import sys
from collections import namedtuple

__all__ = [
    "cone_shock_angle",
    "cone_angle",
    "taylor_maccoll",
    "conical_profile",
    "ConeSolution",
]

ConeSolution = namedtuple("ConeSolution", [
    "shock_angle", "cone_angle", "cone_mach", "cone_p_p1", "cone_rho_rho1", "cone_T_T1",
    "shock_p2_p1", "shock_rho2_rho1", "shock_M2", "deflection"])

DEFAULT_STEP = 1e-4  # radians; RK4 error ~ step^4, far below 1e-8 deg in beta


def _check(mach, gamma):
    if not (gamma > 1.0):
        raise ValueError("gamma must be > 1, got %r" % (gamma,))
    if not (mach > 1.0):
        raise ValueError("a conical shock needs a supersonic upstream Mach number, got %r" % (mach,))


def _oblique(mach, beta, g):
    """(delta, M2, p2/p1, rho2/rho1) behind an oblique shock of angle beta (radians)."""
    m2 = mach * mach
    s = math.sin(beta)
    mn1s = m2 * s * s
    tan_d = 2.0 * (mn1s - 1.0) * math.cos(beta) / s / (m2 * (g + math.cos(2.0 * beta)) + 2.0)
    delta = math.atan(tan_d)
    p21 = 1.0 + 2.0 * g / (g + 1.0) * (mn1s - 1.0)
    r21 = (g + 1.0) * mn1s / ((g - 1.0) * mn1s + 2.0)
    mn2s = (1.0 + 0.5 * (g - 1.0) * mn1s) / (g * mn1s - 0.5 * (g - 1.0))
    mach2 = math.sqrt(mn2s) / math.sin(beta - delta)
    return delta, mach2, p21, r21


def _rhs(theta, vr, vt, g):
    a = 0.5 * (g - 1.0) * (1.0 - vr * vr - vt * vt)
    vrpp = (vt * vt * vr - a * (2.0 * vr + vt / math.tan(theta))) / (a - vt * vt)
    return vt, vrpp


def _rk4(theta, vr, vt, h, g):
    k1r, k1t = _rhs(theta, vr, vt, g)
    k2r, k2t = _rhs(theta + 0.5 * h, vr + 0.5 * h * k1r, vt + 0.5 * h * k1t, g)
    k3r, k3t = _rhs(theta + 0.5 * h, vr + 0.5 * h * k2r, vt + 0.5 * h * k2t, g)
    k4r, k4t = _rhs(theta + h, vr + h * k3r, vt + h * k3t, g)
    return (vr + h / 6.0 * (k1r + 2.0 * k2r + 2.0 * k3r + k4r),
            vt + h / 6.0 * (k1t + 2.0 * k2t + 2.0 * k3t + k4t))


def _mach_from_vprime(vp, g):
    vp2 = vp * vp
    return math.sqrt(2.0 / (g - 1.0) * vp2 / (1.0 - vp2))


def _integrate(mach, beta, g, step=DEFAULT_STEP, record=False):
    """Integrate from the shock (theta = beta, radians) inward to V_t = 0.

    Returns (theta_c, vr_c, post-shock tuple, samples) with theta_c in radians;
    samples is a list of (theta, vr, vt) if record else None.
    """
    delta, mach2, p21, r21 = _oblique(mach, beta, g)
    vp = (2.0 / ((g - 1.0) * mach2 * mach2) + 1.0) ** -0.5
    vr = vp * math.cos(beta - delta)
    vt = -vp * math.sin(beta - delta)
    theta = beta
    samples = [(theta, vr, vt)] if record else None
    h = -step
    while True:
        if theta + h <= 1e-9:
            raise ValueError("no cone found: V_theta never reached 0 (beta = %g deg)" % math.degrees(beta))
        vr1, vt1 = _rk4(theta, vr, vt, h, g)
        if vt1 >= 0.0:
            # the zero lies in this step: refine by bisection on the step length
            lo, hi = 0.0, h  # vt(lo) < 0, vt(hi) >= 0
            for _ in range(60):
                mid = 0.5 * (lo + hi)
                _, vtm = _rk4(theta, vr, vt, mid, g)
                if vtm < 0.0:
                    lo = mid
                else:
                    hi = mid
            hz = 0.5 * (lo + hi)
            vrz, _ = _rk4(theta, vr, vt, hz, g)
            theta += hz
            if record:
                samples.append((theta, vrz, 0.0))
            return theta, vrz, (delta, mach2, p21, r21, vp), samples
        theta += h
        vr, vt = vr1, vt1
        if record:
            samples.append((theta, vr, vt))


def cone_angle(mach, shock_angle_deg, gamma=1.4, step=DEFAULT_STEP):
    """Cone half-angle (degrees) that carries an attached conical shock of angle beta (degrees)."""
    _check(mach, gamma)
    mu = math.asin(1.0 / mach)
    beta = math.radians(shock_angle_deg)
    if not (mu < beta < 0.5 * math.pi):
        raise ValueError("shock angle must lie between the Mach angle %.6g and 90 deg"
                         % math.degrees(mu))
    return math.degrees(_integrate(mach, beta, gamma, step)[0])


def cone_shock_angle(mach, cone_half_angle_deg, gamma=1.4, step=DEFAULT_STEP, tol=1e-10):
    """Attached (weak) conical shock angle in degrees for a cone of the given half-angle.

    Raises ValueError if the cone is too blunt for an attached shock at this Mach number.
    """
    _check(mach, gamma)
    target = float(cone_half_angle_deg)
    if not (0.0 < target < 90.0):
        raise ValueError("cone half-angle must be in (0, 90) deg, got %r" % (cone_half_angle_deg,))
    mu = math.degrees(math.asin(1.0 / mach))

    def f(b):
        return cone_angle(mach, b, gamma, step) - target

    # scan upward from the Mach angle for a bracket; theta_c(beta) rises to a
    # maximum (the detachment limit) and then falls on the strong branch
    lo = mu + 1e-7
    flo = -target
    b, prev = lo, -1.0
    hi = None
    db = 0.25
    while b < 90.0 - 1e-9:
        b = min(b + db, 90.0 - 1e-6)
        try:
            fb = f(b)
        except ValueError:
            break
        if fb >= 0.0:
            hi = b
            break
        if fb + target < prev:  # cone angle started to decrease: past the maximum
            break
        lo, flo, prev = b, fb, fb + target
    if hi is None:
        raise ValueError("cone half-angle %g deg exceeds the maximum (~%.4g deg) for an attached "
                         "shock at M = %g, gamma = %g" % (target, prev, mach, gamma))
    a, c = lo, hi
    while c - a > tol:
        m = 0.5 * (a + c)
        if f(m) < 0.0:
            a = m
        else:
            c = m
    return 0.5 * (a + c)


def taylor_maccoll(mach, cone_half_angle_deg, gamma=1.4, step=DEFAULT_STEP):
    """Full solution on the cone surface and behind the shock (see ConeSolution)."""
    g = gamma
    beta_deg = cone_shock_angle(mach, cone_half_angle_deg, gamma, step)
    theta_c, vr_c, (delta, mach2, p21, r21, _vp), _ = _integrate(mach, math.radians(beta_deg), g, step)
    mc = _mach_from_vprime(vr_c, g)
    e = g / (g - 1.0)
    # isentropic from just behind the shock to the cone surface
    t_ratio = (1.0 + 0.5 * (g - 1.0) * mach2 ** 2) / (1.0 + 0.5 * (g - 1.0) * mc ** 2)  # Tc / T2
    pc_p1 = p21 * t_ratio ** e
    rhoc_rho1 = r21 * t_ratio ** (1.0 / (g - 1.0))
    t21 = p21 / r21
    return ConeSolution(beta_deg, math.degrees(theta_c), mc, pc_p1, rhoc_rho1, t21 * t_ratio,
                        p21, r21, mach2, math.degrees(delta))


def conical_profile(mach, cone_half_angle_deg, gamma=1.4, n=50, step=DEFAULT_STEP):
    """About n samples (theta_deg, p/p1, rho/rho1, T/T1, Mach, ux/V1, ur/V1) from shock to cone.

    ux is the velocity along the cone axis, ur the radial (away from the axis)
    component, both divided by the free-stream speed V1.
    """
    g = gamma
    beta_deg = cone_shock_angle(mach, cone_half_angle_deg, gamma, step)
    _, _, (_delta, mach2, p21, r21, _vp), samples = _integrate(
        mach, math.radians(beta_deg), g, step, record=True)
    # V_max / V1 from the free stream: V1' = [2/((g-1) M^2) + 1]^(-1/2)
    v1p = (2.0 / ((g - 1.0) * mach * mach) + 1.0) ** -0.5
    e = g / (g - 1.0)
    t2_t1 = p21 / r21
    out = []
    stride = max(1, len(samples) // max(1, n - 1))
    idx = list(range(0, len(samples), stride))
    if idx[-1] != len(samples) - 1:
        idx.append(len(samples) - 1)
    for i in idx:
        th, vr, vt = samples[i]
        vp = math.hypot(vr, vt)
        mloc = _mach_from_vprime(vp, g)
        tr = (1.0 + 0.5 * (g - 1.0) * mach2 ** 2) / (1.0 + 0.5 * (g - 1.0) * mloc ** 2)
        ux = (vr * math.cos(th) - vt * math.sin(th)) / v1p
        ur = (vr * math.sin(th) + vt * math.cos(th)) / v1p
        out.append((math.degrees(th), p21 * tr ** e, r21 * tr ** (1.0 / (g - 1.0)), t2_t1 * tr,
                    mloc, ux, ur))
    return out


def _self_check(verbose=True):
    """Compare with published values; returns True if all pass."""
    ok = True

    def report(name, got, want, tol):
        nonlocal ok
        good = abs(got - want) <= tol
        ok &= good
        if verbose:
            print("%-52s %10.4f  (reference %.4g +- %.2g)  %s"
                  % (name, got, want, tol, "ok" if good else "FAIL"))

    # textbook value (cone-shock charts, e.g. NACA Report 1135):
    # M = 2, theta_c = 20 deg -> beta ~ 37.8 deg
    report("M=2.0, cone 20 deg: shock angle [deg]", cone_shock_angle(2.0, 20.0), 37.8, 0.3)
    # slender-cone limit (linearised theory, von Karman & Moore 1932):
    # Cp = theta^2 (2 ln(2 / (B theta)) - 1), B = sqrt(M^2 - 1); 2 deg cone at M = 2.5
    th = math.radians(2.0)
    lin = th * th * (2.0 * math.log(2.0 / (math.sqrt(2.5 ** 2 - 1.0) * th)) - 1.0)
    s = taylor_maccoll(2.5, 2.0)
    report("M=2.5, cone 2 deg: surface Cp / slender-body Cp",
           (s.cone_p_p1 - 1.0) / (0.5 * 1.4 * 2.5 ** 2) / lin, 1.0, 0.05)
    # Mach-angle limit: a very thin cone carries (almost) a Mach wave
    report("M=2.5, cone 0.5 deg: shock angle - Mach angle [deg]",
           cone_shock_angle(2.5, 0.5) - math.degrees(math.asin(1 / 2.5)), 0.0, 0.5)
    # cone angle back from the shock angle (consistency of bisection)
    b = cone_shock_angle(2.5, 20.0)
    report("M=2.5: cone_angle(cone_shock_angle(20)) [deg]", cone_angle(2.5, b), 20.0, 1e-6)
    # step refinement: beta changes by < 1e-6 deg when the RK4 step is halved
    report("M=2.5, 20 deg: beta(step/2) - beta(step) [deg]",
           cone_shock_angle(2.5, 20.0, step=DEFAULT_STEP / 2) - b, 0.0, 1e-6)
    return ok


def main(argv=None):
    ap = argparse.ArgumentParser(
        description="Taylor-Maccoll conical shock angle (prints beta in degrees).")
    ap.add_argument("mach", type=float, nargs="?", help="upstream Mach number (> 1)")
    ap.add_argument("cone", type=float, nargs="?", help="cone half-angle in degrees")
    ap.add_argument("--gamma", type=float, default=1.4, help="ratio of specific heats (default 1.4)")
    ap.add_argument("-v", "--verbose", action="store_true", help="also print the cone-surface state")
    ap.add_argument("--check", action="store_true", help="run the comparisons with published values")
    a = ap.parse_args(argv)
    if a.check:
        return 0 if _self_check() else 1
    if a.mach is None or a.cone is None:
        ap.error("MACH and CONE_HALF_ANGLE_DEG are required (or --check)")
    try:
        s = taylor_maccoll(a.mach, a.cone, a.gamma)
    except ValueError as e:
        print("error: %s" % e, file=sys.stderr)
        return 1
    print("%.6f" % s.shock_angle)
    if a.verbose:
        print("mach_angle %.6f" % math.degrees(math.asin(1.0 / a.mach)))
        print("deflection_at_shock %.6f" % s.deflection)
        print("shock: p2/p1 %.6f rho2/rho1 %.6f M2 %.6f" % (s.shock_p2_p1, s.shock_rho2_rho1, s.shock_M2))
        print("cone surface: Mach %.6f p/p1 %.6f rho/rho1 %.6f T/T1 %.6f Cp %.6f"
              % (s.cone_mach, s.cone_p_p1, s.cone_rho_rho1, s.cone_T_T1,
                 (s.cone_p_p1 - 1.0) / (0.5 * a.gamma * a.mach ** 2)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
