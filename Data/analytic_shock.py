"""Analytic, smeared planar oblique shock in 3-D (numpy only).

Used by the AdaptiveRedistribution tests of the shock sensor
(normal Mach Mn = V.grad(p) / (a |grad p|)) and of Soni's weight function.

Configuration (defaults)
------------------------
Upstream Mach M1 = 2.5, wedge deflection theta = 15 deg, gamma = 1.4,
R = 287.0 J/(kg K), p1 = 1e5 Pa, T1 = 300 K.  The weak-shock angle beta follows
from the theta-beta-Mach relation, the downstream state from Rankine-Hugoniot
(normal velocity u2n = u1n rho1/rho2, tangential velocity continuous).

The configuration is built in a local frame (e1 = xi along the freestream,
e2 = eta, e3 = span).  The shock line lies at angle beta to xi,
t = (cos b, sin b, 0), and its unit normal n = (sin b, -cos b, 0) points
downstream (V1.n > 0).  The flow behind the shock is turned by +theta towards
+eta.  Everything is then rotated by R = Rz(20) Ry(-15) Rx(30) (degrees) so that
neither the freestream nor the shock normal is aligned with an axis, and the
shock plane passes through ``origin`` (default the cube centre (0.5, 0.5, 0.5)).

Smearing
--------
d = (x - x0).n ;  s(d) = 0.5 (1 + tanh(d / delta)) ;
rho, V, p = q1 + s (q2 - q1) ;  T = p / (rho R) ;
rhoU = rho V ;  rhoE = p / (gamma - 1) + 0.5 rho |V|^2.

grad p = (p2 - p1) s'(d) n is parallel to n (and points downstream), so the
Lovely-Haimes normal Mach of the smeared field is Mn(d) = V(d).n / a(d) with
a = sqrt(gamma p / rho); the surface Mn = 1 is exactly the plane d = d*
returned by ``normal_mach_unity_offset()``.

Usage
-----
    from analytic_shock import ObliqueShock
    shock = ObliqueShock()            # defaults above, delta = 1/16
    f = shock.fields(points)          # points: (N, 3) array
    f['rho'], f['U'], f['p'], f['T'], f['rhoU'], f['rhoE'], f['SignedDistance']
    shock.normal_mach_unity_offset()  # d*

``python3 analytic_shock.py`` prints a summary.
"""

import math

import numpy as np

__all__ = [
    "ObliqueShock",
    "MeetingShocks",
    "rotation_matrix",
    "theta_from_beta",
    "weak_shock_angle",
    "normal_shock_ratios",
    "DEFAULT_ROTATION_DEG",
]

# Generic rotation R = Rz(20) Ry(-15) Rx(30), angles in degrees.
DEFAULT_ROTATION_DEG = (30.0, -15.0, 20.0)  # (about x, about y, about z)


# ---------------------------------------------------------------------------
# gas dynamics (private helpers; self-contained on purpose)
# ---------------------------------------------------------------------------
def theta_from_beta(mach, beta_rad, gamma=1.4):
    """Flow deflection (rad) behind an oblique shock of angle beta (rad)."""
    sb = math.sin(beta_rad)
    num = 2.0 / math.tan(beta_rad) * (mach * mach * sb * sb - 1.0)
    den = mach * mach * (gamma + math.cos(2.0 * beta_rad)) + 2.0
    return math.atan(num / den)


def _bisect(f, a, b, tol=1e-15, maxit=400):
    fa = f(a)
    fb = f(b)
    if fa == 0.0:
        return a
    if fb == 0.0:
        return b
    if (fa > 0.0) == (fb > 0.0):
        raise ValueError("bisection interval does not bracket a root")
    for _ in range(maxit):
        m = 0.5 * (a + b)
        fm = f(m)
        if fm == 0.0 or 0.5 * (b - a) < tol:
            return m
        if (fm > 0.0) == (fa > 0.0):
            a, fa = m, fm
        else:
            b, fb = m, fm
    return 0.5 * (a + b)


def weak_shock_angle(mach, theta_rad, gamma=1.4):
    """Weak-solution shock angle beta (rad) for deflection theta (rad)."""
    if mach <= 1.0:
        raise ValueError("upstream Mach number must exceed 1")
    mu = math.asin(1.0 / mach)
    # theta(beta) rises from 0 at beta = mu to a maximum, then falls to 0 at
    # 90 deg: locate the maximum by golden-section search.
    a, b = mu, 0.5 * math.pi
    g = 0.5 * (math.sqrt(5.0) - 1.0)
    c, d = b - g * (b - a), a + g * (b - a)
    fc, fd = theta_from_beta(mach, c, gamma), theta_from_beta(mach, d, gamma)
    while b - a > 1e-14:
        if fc > fd:
            b, d, fd = d, c, fc
            c = b - g * (b - a)
            fc = theta_from_beta(mach, c, gamma)
        else:
            a, c, fc = c, d, fd
            d = a + g * (b - a)
            fd = theta_from_beta(mach, d, gamma)
    beta_max = 0.5 * (a + b)
    if theta_rad > theta_from_beta(mach, beta_max, gamma):
        raise ValueError("deflection exceeds the maximum: detached shock")
    return _bisect(lambda bb: theta_from_beta(mach, bb, gamma) - theta_rad,
                   mu, beta_max)


def normal_shock_ratios(mn1, gamma=1.4):
    """(p2/p1, rho2/rho1, T2/T1, Mn2) across a normal shock of Mach mn1."""
    m2 = mn1 * mn1
    pr = 1.0 + 2.0 * gamma / (gamma + 1.0) * (m2 - 1.0)
    rr = (gamma + 1.0) * m2 / ((gamma - 1.0) * m2 + 2.0)
    tr = pr / rr
    mn2 = math.sqrt(((gamma - 1.0) * m2 + 2.0) / (2.0 * gamma * m2 - (gamma - 1.0)))
    return pr, rr, tr, mn2


def rotation_matrix(ax_deg, ay_deg, az_deg):
    """R = Rz(az) Ry(ay) Rx(ax), angles in degrees."""
    ax, ay, az = (math.radians(v) for v in (ax_deg, ay_deg, az_deg))
    cx, sx = math.cos(ax), math.sin(ax)
    cy, sy = math.cos(ay), math.sin(ay)
    cz, sz = math.cos(az), math.sin(az)
    rx = np.array([[1.0, 0.0, 0.0], [0.0, cx, -sx], [0.0, sx, cx]])
    ry = np.array([[cy, 0.0, sy], [0.0, 1.0, 0.0], [-sy, 0.0, cy]])
    rz = np.array([[cz, -sz, 0.0], [sz, cz, 0.0], [0.0, 0.0, 1.0]])
    return rz @ ry @ rx


# ---------------------------------------------------------------------------
class ObliqueShock:
    """Smeared planar oblique shock, rotated to a generic orientation."""

    def __init__(self, mach=2.5, theta_deg=15.0, gamma=1.4, gas_constant=287.0,
                 p1=1.0e5, T1=300.0, origin=(0.5, 0.5, 0.5), delta=1.0 / 16.0,
                 rotation_deg=DEFAULT_ROTATION_DEG):
        if delta <= 0.0:
            raise ValueError("smearing width delta must be positive")
        self.mach = float(mach)
        self.theta_deg = float(theta_deg)
        self.gamma = float(gamma)
        self.R = float(gas_constant)
        self.delta = float(delta)
        self.origin = np.asarray(origin, dtype=float).reshape(3)
        self.rotation_deg = tuple(float(v) for v in rotation_deg)
        self.rotation = rotation_matrix(*self.rotation_deg)

        g = self.gamma
        theta = math.radians(self.theta_deg)
        beta = weak_shock_angle(self.mach, theta, g)
        self.beta = beta
        self.beta_deg = math.degrees(beta)

        # upstream state
        self.p1 = float(p1)
        self.T1 = float(T1)
        self.rho1 = self.p1 / (self.R * self.T1)
        self.a1 = math.sqrt(g * self.p1 / self.rho1)
        self.V1mag = self.mach * self.a1

        # local frame vectors
        e1 = np.array([1.0, 0.0, 0.0])
        t_loc = np.array([math.cos(beta), math.sin(beta), 0.0])
        n_loc = np.array([math.sin(beta), -math.cos(beta), 0.0])
        V1_loc = self.V1mag * e1
        u1n = float(V1_loc @ n_loc)
        u1t = float(V1_loc @ t_loc)
        self.mn1 = u1n / self.a1
        pr, rr, tr, mn2 = normal_shock_ratios(self.mn1, g)
        self.pressure_ratio = pr
        self.density_ratio = rr
        self.temperature_ratio = tr
        self.p2 = self.p1 * pr
        self.rho2 = self.rho1 * rr
        self.T2 = self.p2 / (self.rho2 * self.R)
        u2n = u1n * self.rho1 / self.rho2
        V2_loc = u1t * t_loc + u2n * n_loc
        self.u1n, self.u2n, self.ut = u1n, u2n, u1t
        self.a2 = math.sqrt(g * self.p2 / self.rho2)
        self.M2 = float(np.linalg.norm(V2_loc)) / self.a2
        self.mn2 = u2n / self.a2

        # global (rotated) configuration
        R = self.rotation
        self.freestream_direction = R @ e1
        self.normal = R @ n_loc            # unit shock normal, downstream
        self.tangent = R @ t_loc           # in-plane direction of the shock line
        self.span = R @ np.array([0.0, 0.0, 1.0])
        self.V1 = R @ V1_loc
        self.V2 = R @ V2_loc
        self._dstar = {}

    # -- smearing ------------------------------------------------------------
    def signed_distance(self, points):
        pts = np.asarray(points, dtype=float).reshape(-1, 3)
        return (pts - self.origin) @ self.normal

    def blend(self, d):
        return 0.5 * (1.0 + np.tanh(np.asarray(d, dtype=float) / self.delta))

    def _state(self, s):
        s = np.asarray(s, dtype=float)
        rho = self.rho1 + s * (self.rho2 - self.rho1)
        p = self.p1 + s * (self.p2 - self.p1)
        U = self.V1[None, :] + s.reshape(-1, 1) * (self.V2 - self.V1)[None, :]
        return rho, U, p

    def normal_mach_of_distance(self, d):
        """Exact normal Mach Mn = V.n / a of the smeared field at distance d."""
        d = np.asarray(d, dtype=float)
        s = self.blend(d).reshape(-1)
        rho, U, p = self._state(s)
        mn = (U @ self.normal) / np.sqrt(self.gamma * p / rho)
        return mn.reshape(d.shape) if d.shape else float(mn[0])

    def normal_mach(self, points):
        """Exact Lovely-Haimes normal Mach V.grad(p)/(a |grad p|) at points."""
        return self.normal_mach_of_distance(self.signed_distance(points))

    def normal_mach_unity_offset(self, tol=1e-12):
        """Signed distance d* at which the smeared field has Mn = 1.

        Mn(d) falls monotonically from Mn1 > 1 upstream to Mn2 < 1 downstream;
        bisection on [-40 delta, 40 delta] to an interval half-width <= tol.
        """
        key = float(tol)
        if key not in self._dstar:
            f = lambda d: self.normal_mach_of_distance(d) - 1.0
            self._dstar[key] = _bisect(f, -40.0 * self.delta, 40.0 * self.delta,
                                       tol=key)
        return self._dstar[key]

    # -- evaluation ------------------------------------------------------------
    def fields(self, points):
        """Dict of arrays at the (N, 3) points.

        rho (N,), U (N, 3), p (N,), T (N,), rhoU (N, 3), rhoE (N,),
        SignedDistance (N,).
        """
        d = self.signed_distance(points)
        s = self.blend(d)
        rho, U, p = self._state(s)
        T = p / (rho * self.R)
        rhoU = rho[:, None] * U
        rhoE = p / (self.gamma - 1.0) + 0.5 * rho * np.einsum("ij,ij->i", U, U)
        return {"rho": rho, "U": U, "p": p, "T": T, "rhoU": rhoU, "rhoE": rhoE,
                "SignedDistance": d}

    def field_data(self):
        """Scalars/vectors to store as field data in a dataset."""
        return {
            "ShockNormal": self.normal.copy(),
            "ShockOrigin": self.origin.copy(),
            "SmearingWidth": self.delta,
            "UpstreamMach": self.mach,
            "DeflectionAngle": self.theta_deg,
            "ShockAngle": self.beta_deg,
            "Gamma": self.gamma,
            "GasConstant": self.R,
            "NormalMachUnityOffset": self.normal_mach_unity_offset(),
        }

    def summary(self):
        fmt = lambda v: "(" + ", ".join("%.12g" % x for x in v) + ")"
        lines = [
            "M1 = %g, theta = %g deg, gamma = %g, R = %g" % (
                self.mach, self.theta_deg, self.gamma, self.R),
            "beta (weak) = %.12g deg" % self.beta_deg,
            "Mn1 = %.12g, Mn2 = %.12g, M2 = %.12g" % (self.mn1, self.mn2, self.M2),
            "p2/p1 = %.12g, rho2/rho1 = %.12g, T2/T1 = %.12g" % (
                self.pressure_ratio, self.density_ratio, self.temperature_ratio),
            "rho1 = %.12g, p1 = %.12g, T1 = %.12g, |V1| = %.12g" % (
                self.rho1, self.p1, self.T1, self.V1mag),
            "rho2 = %.12g, p2 = %.12g, T2 = %.12g" % (self.rho2, self.p2, self.T2),
            "rotation Rz(%g) Ry(%g) Rx(%g)" % (
                self.rotation_deg[2], self.rotation_deg[1], self.rotation_deg[0]),
            "freestream dir = " + fmt(self.freestream_direction),
            "shock normal n = " + fmt(self.normal),
            "V1 = " + fmt(self.V1),
            "V2 = " + fmt(self.V2),
            "origin = " + fmt(self.origin) + ", delta = %.12g" % self.delta,
            "d* (Mn = 1) = %.15g" % self.normal_mach_unity_offset(),
        ]
        return "\n".join(lines)


# ---------------------------------------------------------------------------
class MeetingShocks:
    """Two smeared plane shocks that meet at a line (a kinked shock sheet).

    Both are ObliqueShock's of the same freestream (Mach, deflection, gas),
    through the same ``origin``; the second is turned about the freestream
    direction by ``turn_deg`` (so its upstream state and strength are the
    first's, its normal is not). With dA, dB the signed distances to the two
    planes (positive downstream), the field at x is shock A's at dA where
    dA >= dB and shock B's at dB elsewhere: d = max(dA, dB) is continuous,
    and so are rho, p and T (both shocks have the same jump); the velocity
    behind the shocks jumps across the bisecting half-plane dA = dB (a slip
    surface). The surface Mn = 1 is the two half-planes d = d*: shock A's
    plane offset by d* where dA > dB, shock B's where dB > dA, meeting at the
    line through ``origin + d* (nA + nB) / (1 + nA.nB)`` along nA x nB.
    The angle between the two planes is acos(sin^2 b + cos^2 b cos(turn))
    (b the shock angle): 35.6 degrees for the defaults (M 2.5, 15 deg,
    turn 45 deg).
    """

    def __init__(self, turn_deg=45.0, rotation_deg=DEFAULT_ROTATION_DEG, **kwargs):
        ax, ay, az = rotation_deg
        self.a = ObliqueShock(rotation_deg=(ax, ay, az), **kwargs)
        # R Rx(turn) = Rz(az) Ry(ay) Rx(ax + turn): the same freestream R e1.
        self.b = ObliqueShock(rotation_deg=(ax + turn_deg, ay, az), **kwargs)
        self.normals = (self.a.normal, self.b.normal)
        self.origin = self.a.origin
        self.angle_deg = math.degrees(math.acos(min(1.0, abs(float(self.a.normal @ self.b.normal)))))
        self.line_direction = np.cross(self.a.normal, self.b.normal)
        self.line_direction /= np.linalg.norm(self.line_direction)

    def normal_mach_unity_offset(self):
        return self.a.normal_mach_unity_offset()

    def fields(self, points):
        """As ObliqueShock.fields, plus Side (0: shock A governs, 1: B)."""
        fa, fb = self.a.fields(points), self.b.fields(points)
        on_b = fb["SignedDistance"] > fa["SignedDistance"]
        out = {}
        for name, va in fa.items():
            vb = fb[name]
            mask = on_b.reshape((-1,) + (1,) * (va.ndim - 1))
            out[name] = np.where(mask, vb, va)
        out["Side"] = on_b.astype(np.float64)
        return out


if __name__ == "__main__":
    print(ObliqueShock().summary())
