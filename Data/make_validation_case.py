#!/usr/bin/env python3
"""Make small steady rhoCentralFoam solutions for the validation matrix.

Usage (from anywhere):
    python3 Data/make_validation_case.py CASE_NAME OUTPUT.vtu [--keep DIR] [--refine F]
    python3 Data/make_validation_case.py --list
  CASE_NAME   one of the cases below (--list)
  OUTPUT.vtu  the zlib-compressed binary .vtu written (Data/foam_vtu.py)
  --keep DIR  build the OpenFOAM case in DIR and keep it (DIR must not exist,
              be empty, or hold an earlier case of this script, which is then
              replaced); default: a temporary directory, removed at the end
              (a case that fails is always kept, its path is printed)
  --refine F  refine the mesh uniformly by F: blockMesh cell counts x F,
              Gmsh sizes / F (grading, geometry and solver settings kept)
  --list      the cases and their exact shock angles
Needs: gmsh (4.8), Debian packages openfoam (v1912) and paraview /
python3-paraview (pvpython 5.11).  The solver runs serially (one core, no
MPI) and takes at most ~2.5 minutes per case; the mesh and the conversion add
~5 s.  Gmsh runs with one thread: the meshes, and so the files, are
reproducible.  Internally the script calls itself under pvpython for the
conversion (--convert, not for use by hand); it reuses Data/foam_case.py,
Data/foam_vtu.py, Data/theta_beta_mach.py, Data/taylor_maccoll.py and
cone_geometry() of Data/convert_cone20Ma2p5.py.

The cases are inviscid, and none of them is bundled in Data/ or used by the
tests.  The gas is the normalised gas of OpenFOAM's wedge15Ma5 tutorial, as in
Data/make_cone20Ma2p5.sh: R = 1/1.4, Cp = 2.5, gamma = 1.4, speed of sound 1
at T = 1; free stream p = 1, T = 1, U = (Mach, 0, 0), fixedValue at the inflow
boundaries, zeroGradient at the outlet (supersonic everywhere on it), slip
walls.  The meshes are graded towards the body.

  wedge10Ma3     2-D, Mach 3 over a 10 deg wedge (ramp), blockMesh hexahedra
                 one cell deep (frontAndBack empty), the layout of the
                 wedge15Ma5 tutorial: inlet x = -0.15, tip at the origin, ramp
                 to x = 0.3, symmetry planes y = 0 (upstream of the tip) and
                 y = 0.2 (the shock, 27.38 deg, leaves through the outlet at
                 y = 0.155).  30 + 70 cells along x and 70 across (7000): the
                 cells shrink towards the tip (x ratio 2.5 in both blocks) and
                 towards the wall (y ratio 3): sqrt(cell area) 0.002 .. 0.006.
  wedge20Ma4tri  2-D, Mach 4 over a 20 deg wedge: the same layout with the top
                 at y = 0.25 (shock 32.46 deg, y = 0.191 at the outlet); the
                 cross-section is meshed with Gmsh triangles (Frontal-Delaunay)
                 and extruded one cell deep into prisms (VTK wedges, 5510).
                 Size 0.003 at the wall and the tip, growing linearly with the
                 distance from them to 0.009 at 0.12.
  wedge12Ma6tet  3-D slab, Mach 6 over a 12 deg wedge: inlet x = -0.1, ramp to
                 x = 0.3, top y = 0.14 (shock 19.55 deg, y = 0.107 at the
                 outlet), span z = -0.03 .. 0.03 between two symmetry planes
                 (sideBack, sideFront); Gmsh Delaunay tetrahedra (19776), size
                 0.0052 at the wall and the tip growing to 0.0125 at 0.08.
  cone15Ma3      3-D, Mach 3 over a sharp cone of 15 deg half-angle, quarter
                 domain (symmetry planes y = 0 and z = 0: symmetryY,
                 symmetryZ), tip at the origin, axis +x, the cone leaves the
                 domain through the outlet x = 1; inlet x = -0.1, side
                 (farfield, free stream) r = 0.6; the shock (Taylor-Maccoll
                 25.26 deg) meets the outlet at r = 0.47.  Gmsh tetrahedra
                 (20646) with the size field of Data/make_cone20Ma2p5.sh:
                 h = 0.016 + 0.016 rho (rho: distance from the tip) in the band
                 13.5 .. 29 deg of polar angle (cone, conical flow, shock),
                 growing by 0.25 rho per radian outside it, at most 0.08.
  cone25Ma2      as cone15Ma3, Mach 2 and a 25 deg cone (shock 42.53 deg,
                 r = 0.92 at the outlet): side r = 1.1, band 23.5 .. 46 deg,
                 h = 0.018 + 0.03 rho, at most 0.1 (20811 tetrahedra).
  cone15Ma3w     cone15Ma3 meshed as before anyone knows where the shock is:
                 the band only hugs the cone (13.5 .. 17 deg, h = 0.010 +
                 0.012 rho), the cells grow by 0.2 rho per radian from it,
                 so at the shock they are about 1.7x cone15Ma3's (19303
                 tetrahedra, 4378 nodes as cone15Ma3's 4398). Not in the
                 CTest matrix: its solution's shock is +0.61 deg off
                 Taylor-Maccoll (mean of the meridians), so a fit on it
                 cannot be held to 0.5 of theory; the payoff benchmark's
                 case of an input not refined at the shock.
  cylinderMa3    2-D blunt body: Mach 3 over a circular cylinder of radius 0.5
                 centred at the origin, upper half (symmetry plane y = 0 in
                 front of the body), front half only: the outlet is the plane
                 x = 0 above the body, where the flow is supersonic.  The
                 inflow boundary follows Billig's bow-shock correlation
                 (Billig 1967: standoff 0.386 R exp(4.67 / M^2) = 0.324, shock
                 radius of curvature 1.386 R exp(1.8 / (M - 1)^0.75)) moved
                 upstream by 0.15 + 0.1 y.  blockMesh hexahedra (9900), five
                 blocks side by side between rays from the centre 18 deg apart
                 (so the lines off the body are nearly radial: non-orthogonality
                 at most 47, mean 20 deg), 90 cells off the body (the outermost
                 3x the innermost) x 110 along it.
  wedge10Ma3o1   wedge10Ma3 (the same mesh) with FIRST-order reconstruction:
                 reconstruct(rho|U|T) upwind, i.e. the face values are the
                 cells' own.  The shock is ~2.7x wider (10-90% of the p jump
                 0.026 across the shock at x = 0.2 instead of 0.0097).
  cone15Ma3o1    cone15Ma3 (the same mesh) with first-order reconstruction.
  sphereMa3      3-D blunt body: Mach 3 over a sphere of radius 0.5 centred at
                 the origin, quarter domain (symmetry planes y = 0 and z = 0:
                 symmetryY, symmetryZ), front half only: the outlet is the
                 plane x = 0, where the flow is supersonic.  The inflow
                 boundary is the sphere of radius 1.25 about (0.45, 0, 0),
                 0.15-0.21 upstream of Billig's bow shock of a sphere
                 (standoff 0.143 R exp(3.24 / M^2) = 0.102, shock radius of
                 curvature 1.143 R exp(0.54 / (M - 1)^1.2)).  Gmsh
                 tetrahedra (17954), size 0.03 at the wall growing linearly
                 with the distance from it to 0.07 at 0.5: nothing finer at
                 the shock (about 3 cells in the standoff).

Schemes and time steps: the second-order cases use what
Data/make_wedge15Ma5.sh found to give steady rhoCentralFoam solutions: the
Tadmor flux with Minmod/MinmodV limiters, Euler in time.  The time step is
adjusted to a fixed Courant number (adjustTimeStep, maxCo 0.2 for the 2-D
wedges, 0.3 for the tetrahedra and the cylinder, where the cost matters; with
tetrahedra a handful of poor cells next to the tip or the wall set the step).
sphereMa3 limits its gradients (gradSchemes cellLimited Gauss linear 1; the
others use Gauss linear): Minmod's slope ratio is built from the gradient,
and on tetrahedra at a normal shock of pressure ratio 10 the unlimited one
overshoots; rhoCentralFoam then drives a cell at the shock to a negative T
(sqrt of a negative number).  Measured with Gauss linear: this mesh runs,
the same domain meshed 1.2x finer (--refine 1.2, 30218 tetrahedra) fails at
t = 0.031, and AdaptToShocks' mesh of the solution (99498 tetrahedra) at
t = 0.0084; with the limited gradient both run.
The initial field is the free stream everywhere (impulsive start).  endTime:
  wedge10Ma3(o1) 0.75 (5 flow-throughs of the length 0.45 at U = 3)
  wedge20Ma4tri  0.6  (5.3 flow-throughs)
  wedge12Ma6tet  0.125 (1.9 flow-throughs: steady from t = 0.1 on; in a 0.3
                 long run of a coarser variant the rms change stayed at
                 0.011-0.014% from t = 0.1 to 0.3, a flicker of shock cells)
  cone15Ma3(o1)  0.8  (2.2 flow-throughs of the length 1.1: steady from t = 0.7)
  cone25Ma2      2.0: slow, the waves running upstream in the shock layer
                 (u - c ~ 0.45 at Mach 1.4 on the cone) cross it in ~2.2; the
                 rms change falls by ~0.7 per 0.1 to 0.033% at t = 2.
  sphereMa3      3.0 (18 R/U; steady from about 2.5: rms dp 0.0045 % between
                 the last writes, the relief of the third dimension flushes
                 the stagnation region faster than the cylinder's)
  cylinderMa3    9.0 (54 R/U): the impulsive start leaves a pocket of hot gas
                 (T 3.5 instead of T0 = 2.8) at the stagnation point, where the
                 flow is slow; as it is flushed out the bow shock creeps
                 outward (x = -0.64 at t = 0.25, -0.84 at t = 3, -0.85 at
                 t = 4.5 on) and the rms change of p falls by ~0.8 per 0.25
                 only (2.1% at t = 3, 0.088% at t = 7, 0.035% at t = 9).
                 Initialising the shock layer with Billig's shock and the
                 Rankine-Hugoniot state behind it did not help (the shock
                 overshoots outward, then creeps back: 0.9% at t = 3), so the
                 impulsive start is kept.

Steadiness: p (cell values) at the last two written times is compared; the
script stops (keeping the case) unless the rms change is below 0.1% of the p
range.  The maximum change is reported too (a few shock cells may flicker,
see Data/make_wedge15Ma5.sh).  Results (solver wall time on one core of a
2-core machine with the other core busy; rms and max change of p between the
last two writes in % of the p range; exact shock angle; measured angle, mean
of the planes or meridians, see the physics check):

  case           cells                 solver   steps   rms dp    max dp  exact    measured
  wedge10Ma3     7000 hexahedra          42 s    7399  0.0002%   0.007%  27.383   27.539
  wedge20Ma4tri  5510 prisms             59 s   16436  0.0005%   0.012%  32.464   32.624
  wedge12Ma6tet  19776 tetrahedra       115 s    5280  0.040%    1.9%    19.553   19.754
  cone15Ma3      20646 tetrahedra        98 s    4807  0.011%    0.51%   25.259   25.714
  cone25Ma2      20811 tetrahedra       117 s    5998  0.033%    0.47%   42.532   43.171
  cylinderMa3    9900 hexahedra         146 s   17842  0.035%    0.39%   standoff 0.349 (0.698 R;
                                                                         Billig 0.324), p0'/p1 12.061
                                                                         (pitot 12.061)
  wedge10Ma3o1   7000 hexahedra          28 s    7311  0         0       27.383   27.859
  cone15Ma3o1    20646 tetrahedra        66 s    4791  0.0078%   0.037%  25.259   25.932
  sphereMa3      17954 tetrahedra       289 s    8982  0.0045%   0.29%   standoff 0.1111 (0.222 R;
                                                                         Billig 0.1025), p0'/p1 11.887
                                                                         (pitot 12.061); limited
                                                                         gradients (Gauss linear:
                                                                         142 s, 8900 steps, 0.1105,
                                                                         12.118)

Field data of the .vtu (doubles):
  all       Gamma, GasConstant (from constant/thermophysicalProperties),
            UpstreamMach (from the inlet fixedValue of U and T: 1.000003 x the
            nominal Mach, since R = 8314.47 / 11640.3 is not exactly 1/1.4),
            FlowDirection (unit), SchemeOrder (1 or 2), SteadinessRmsDp,
            SteadinessMaxDp (last two writes, fractions of the p range),
            SolutionTime
  wedges    WedgeAngle (deg, fitted to the points of the "obstacle" patch),
            WedgeTip (x, y, z; z at mid-span), WedgeSpan (0 0 1),
            ShockAngleThetaBetaMach (deg, weak solution, Data/theta_beta_mach.py),
            ShockNormal (unit normal of the exact shock plane through the tip
            and along the span, pointing downstream), ShockPressureRatio (p2/p1)
  cones     ConeHalfAngle (deg), ConeTip, ConeAxis (fitted to the points of
            the "cone" patch by Data/convert_cone20Ma2p5.py's cone_geometry),
            ShockAngleTaylorMaccoll (deg, Data/taylor_maccoll.py),
            ConePressureRatioTaylorMaccoll, ShockPressureRatioTaylorMaccoll
  sphere    SphereCentre, SphereRadius (the nominal values, checked within
            1e-6 against a sphere fitted to the points of the "sphere"
            patch), NormalShockPressureRatio, StagnationPressureRatio,
            ShockStandoffBillig (Billig's sphere correlation), as the cylinder's
  cylinder  CylinderCentre (z at mid-span), CylinderRadius, CylinderAxis
            (the nominal values, checked within 1e-6 against a circle fitted
            to the points of the "cylinder" patch),
            NormalShockPressureRatio (p2/p1 across the normal shock on the
            stagnation line), StagnationPressureRatio (p0'/p1, Rayleigh pitot
            formula: exact at the inviscid stagnation point),
            ShockStandoffBillig (Billig's correlation, approximate: a test
            should measure the standoff from the solution)
Arrays: rho, U, p, T, rhoU, rhoE as point and cell data (Data/foam_vtu.py).

Physics check (after the conversion, on the file read back; the script fails
if it fails).  Wedges and cones: the shock angle measured on lines normal to
the flow at 12 stations 0.15 .. 0.9 of the body length (the outermost crossing
of p = (p1 + p2)/2, p2 the exact value behind the shock, linear in the cells;
a line through the tip fitted), on the mid-span plane (the 3-D slab: also at
+-span/4) or on the meridians 0, 45, 90 deg of the quarter cone; each must be
within 1 deg of the theory (1.5 deg for the first-order cases).  Cylinder
and sphere: the
standoff on the stagnation line (the same crossing with the normal shock's p2)
within 25% of Billig's correlation and the stagnation-point pressure within 3%
of the pitot formula.
"""

import argparse
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__ if "__file__" in globals() else sys.argv[0]))
sys.path.insert(0, HERE)
import foam_case  # noqa: E402
import taylor_maccoll  # noqa: E402
import theta_beta_mach  # noqa: E402

FOAM_BASHRC = "/usr/share/openfoam/etc/bashrc"
MARKER = ".make_validation_case"
STEADY_RMS = 1e-3        # rms dp / p range between the last two writes
SHOCK_ANGLE_TOL = {2: 1.0, 1: 1.5}   # deg, measured vs theory, by scheme order
GAMMA = 1.4              # the normalised gas (checked again from the case files)

# ---------------------------------------------------------------------------- the cases
# Common keys: kind (wedge | cone | cylinder | sphere), mesher, mach, order (1 | 2),
# end (endTime), write (writeInterval), maxco.  The second- and first-order
# variants of a case share their geometry and mesh parameters.
_WEDGE10 = dict(kind="wedge", mesher="blockMesh", mach=3.0, angle=10.0,
                x0=-0.15, x1=0.3, height=0.2, span=0.01,
                nx=(30, 70), ny=70, grade_x=2.5, grade_y=3.0,
                end=0.75, write=0.05, maxco=0.2)
# Gmsh tetrahedra, second order unless a case says otherwise: a cone from
# x0 to x1 (band: the polar angles, degrees, of the finer cells about the
# shock, h0 at the tip to h1 at x1), and a wedge in a slab `span` deep.
_TET_CONE = dict(kind="cone", mesher="gmsh3d", order=2, x0=-0.1, x1=1.0, grow=0.25, maxco=0.3)
_TET_WEDGE = dict(kind="wedge", mesher="gmsh3d", order=2, x0=-0.1, x1=0.3, maxco=0.3)
_CONE15 = dict(_TET_CONE, mach=3.0, angle=15.0, radius=0.6,
               band=(13.5, 29.0), h0=0.016, h1=0.016, hmax=0.08, end=0.8, write=0.1)
# Local time stepping (--lts): rhoCentralFoam's steady mode, ddtSchemes
# localEuler.  Every cell steps with its own time step at maxCo (the case's
# times `maxco`; the reciprocal smoothed so that neighbours differ by at most
# a factor 1 + rDeltaTSmoothingCoeff), the run's time is the iteration count
# (deltaT 1), and a fixed number of iterations is run, written every `write`.
# At the case's maxCo 0.2, wedge10Ma3's shock flickers with local steps: p's
# rms change between writes stays at 0.06 % of its range (0.11 % with
# rDeltaTSmoothingCoeff 0.02) instead of falling to Euler's 0.0002 %; at 0.1
# it falls to 0.002 %, steady from iteration 2250 of the original mesh.
LTS = dict(iterations=6000, write=250, smoothing=1.0, maxco=0.5)
CASES = {
    "wedge10Ma3": dict(_WEDGE10, order=2),
    "wedge20Ma4tri": dict(kind="wedge", mesher="gmsh2d", mach=4.0, angle=20.0, order=2,
                          x0=-0.15, x1=0.3, height=0.25, span=0.01,
                          hmin=0.003, hmax=0.009, dgrow=0.12,
                          end=0.6, write=0.05, maxco=0.2),
    "wedge12Ma6tet": dict(_TET_WEDGE, mach=6.0, angle=12.0, height=0.14, span=0.06,
                          hmin=0.0052, hmax=0.0125, dgrow=0.08, end=0.125, write=0.025),
    "cone15Ma3": dict(_CONE15, order=2),
    "cone25Ma2": dict(_TET_CONE, mach=2.0, angle=25.0, radius=1.1,
                      band=(23.5, 46.0), h0=0.018, h1=0.03, hmax=0.1, end=2.0, write=0.1),
    "cylinderMa3": dict(kind="cylinder", mesher="blockMesh", mach=3.0, order=2,
                        radius=0.5, span=0.01, margin=(0.15, 0.1),
                        blocks=5, n_normal=90, n_along=110, grade_normal=3.0,
                        end=9.0, write=0.25, maxco=0.3),
    "wedge10Ma3o1": dict(_WEDGE10, order=1),
    "cone15Ma3o1": dict(_CONE15, order=1),
    # Added after the plugin's defaults were settled, to try them on cases
    # nobody had looked at: a Mach 2.5 wedge on triangles, a weak conical
    # shock (upstream normal Mach 1.22; the compression behind it is 0.58 of
    # the shock's own jump), a first-order Mach 5 wedge of 8 degrees.
    "wedge18Ma2p5tri": dict(kind="wedge", mesher="gmsh2d", mach=2.5, angle=18.0, order=2,
                            x0=-0.15, x1=0.3, height=0.33, span=0.01,
                            hmin=0.003, hmax=0.009, dgrow=0.12,
                            end=1.0, write=0.05, maxco=0.2),
    "cone10Ma4": dict(_TET_CONE, mach=4.0, angle=10.0, radius=0.45,
                      band=(8.5, 21.5), h0=0.013, h1=0.015, hmax=0.07, end=0.6, write=0.1),
    "wedge8Ma5o1": dict(_WEDGE10, mach=5.0, angle=8.0, height=0.14, end=0.5, write=0.05, order=1),
    # Added on 7 December: a Mach 3 wedge of 15 degrees on tetrahedra, a slab
    # 0.15 deep. In the CTest matrix since each side of the prism stack has
    # its own closure apices (closure tetrahedra 5.4-5.5 degrees, 4.7 before,
    # the floor 5; the new cells at the shock 0.31 of the input's size since
    # the refill's free points off S, 0.345 before). Meshed 1.25x finer
    # since the seventh session (33,693 tetrahedra, hmin 0.008 -> 0.0064,
    # hmax 0.02 -> 0.016): on the first mesh (18,061) its shock was +0.51 off
    # theory and the plane +0.53, over the 0.5; now +0.36 and +0.41.
    # Steady at endTime 0.3 (rms dp 0.0094 % between the last writes; 245 s).
    "wedge15Ma3tet": dict(_TET_WEDGE, mach=3.0, angle=15.0, height=0.22, span=0.15,
                          hmin=0.0064, hmax=0.016, dgrow=0.1, end=0.3, write=0.05),
    # Added on 7 December after the Rankine-Hugoniot centring, to try it on
    # cones nobody had looked at: Mach 3.5 at 12 degrees, Mach 2.5 at 30.
    "cone12Ma3p5": dict(_TET_CONE, mach=3.5, angle=12.0, radius=0.5,
                        band=(10.5, 24.0), h0=0.014, h1=0.016, hmax=0.08, end=0.6, write=0.1),
    "cone30Ma2p5": dict(_TET_CONE, mach=2.5, angle=30.0, radius=1.1,
                        band=(28.5, 46.5), h0=0.018, h1=0.03, hmax=0.1, end=1.5, write=0.1),
    # Added after the refill's free points off S, to try them on 3-D cases
    # nobody had looked at: a Mach 2.5 wedge of 20 degrees on tetrahedra (a
    # slab 0.12 deep; steady at 0.8, not at 0.4: rms dp 0.72 % between the
    # last writes; too thin for prism layers, see TestValidationCase), a
    # Mach 4 cone of 20 degrees.
    "wedge20Ma2p5tet": dict(_TET_WEDGE, mach=2.5, angle=20.0, height=0.35, span=0.12,
                            hmin=0.007, hmax=0.02, dgrow=0.1, end=0.8, write=0.1),
    "cone20Ma4": dict(_TET_CONE, mach=4.0, angle=20.0, radius=0.7,
                      band=(18.5, 33.0), h0=0.015, h1=0.02, hmax=0.08, end=0.8, write=0.1),
    # Added on 7 December (fifth session): the 3-D blunt body, the paper's
    # capsule in miniature, which nobody had tried: Mach 3 over a sphere on
    # tetrahedra graded from the wall only (nothing finer at the shock).
    "sphereMa3": dict(kind="sphere", mesher="gmsh3d", mach=3.0, order=2, radius=0.5,
                      outer=(0.45, 1.25), hmin=0.03, hmax=0.07, dgrow=0.5,
                      end=3.0, write=0.25, maxco=0.3, grad="cellLimited Gauss linear 1"),
    # Added on 7 December (seventh session): cone15Ma3 meshed as one would
    # before knowing where the shock is, graded from the cone's surface only
    # (the band 13.5 .. 17 deg hugs the cone; the shock at 25.26 deg is in
    # cells growing away from it).
    "cone15Ma3w": dict(_CONE15, order=2, band=(13.5, 17.0), h0=0.010, h1=0.012, grow=0.2),
}


def log(name, msg):
    print("[%s] %s" % (name, msg), flush=True)


# ---------------------------------------------------------------------------- theory
def billig(mach, radius):
    """Billig's (1967) bow shock of a circular cylinder: (standoff, shock
    radius of curvature at the axis, Mach angle in rad)."""
    delta = 0.386 * radius * math.exp(4.67 / mach ** 2)
    rc = 1.386 * radius * math.exp(1.8 / (mach - 1.0) ** 0.75)
    return delta, rc, math.asin(1.0 / mach)


def billig_sphere(mach, radius):
    """Billig's (1967) bow shock of a sphere: (standoff, shock radius of
    curvature at the axis)."""
    return (0.143 * radius * math.exp(3.24 / mach ** 2),
            1.143 * radius * math.exp(0.54 / (mach - 1.0) ** 1.2))


def billig_shock_x(y, mach, radius):
    """x of Billig's shock at height y (cylinder centred at the origin)."""
    delta, rc, mu = billig(mach, radius)
    cot2 = 1.0 / math.tan(mu) ** 2
    return -(radius + delta) + rc * cot2 * (math.sqrt(1.0 + (y * math.tan(mu) / rc) ** 2) - 1.0)


def pitot_ratio(mach, gamma=GAMMA):
    """p0'/p1, stagnation pressure behind a normal shock over free-stream static pressure."""
    g = gamma
    m2 = mach * mach
    return (((g + 1.0) ** 2 * m2 / (4.0 * g * m2 - 2.0 * (g - 1.0))) ** (g / (g - 1.0))
            * (1.0 - g + 2.0 * g * m2) / (g + 1.0))


def theory(c):
    """The exact answer a test needs, as (name, values) pairs, plus a one-line summary."""
    if c["kind"] == "wedge":
        beta = theta_beta_mach.shock_angle(c["mach"], c["angle"], GAMMA)
        jump = theta_beta_mach.oblique_shock_jump(c["mach"], beta, GAMMA)
        return beta, jump.p2_p1, "theta-beta-Mach beta = %.4f deg, p2/p1 = %.4f" % (beta, jump.p2_p1)
    if c["kind"] == "cone":
        tm = taylor_maccoll.taylor_maccoll(c["mach"], c["angle"], GAMMA)
        return tm.shock_angle, tm.shock_p2_p1, ("Taylor-Maccoll beta = %.4f deg, cone p/p1 = %.4f"
                                                % (tm.shock_angle, tm.cone_p_p1))
    beta = 90.0
    jump = theta_beta_mach.oblique_shock_jump(c["mach"], beta, GAMMA)
    standoff = (billig_sphere if c["kind"] == "sphere" else billig)(c["mach"], c["radius"])[0]
    return beta, jump.p2_p1, ("normal shock p2/p1 = %.4f, pitot p0'/p1 = %.4f, Billig standoff %.4f"
                              % (jump.p2_p1, pitot_ratio(c["mach"]), standoff))


# ---------------------------------------------------------------------------- OpenFOAM files
def header(cls, obj, location=None):
    loc = '\n    location    "%s";' % location if location else ""
    return ("FoamFile\n{\n    version     2.0;\n    format      ascii;\n    class       %s;%s\n"
            "    object      %s;\n}\n" % (cls, loc, obj))


def write(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(text)


# patch roles: inflow (fixedValue free stream), outflow (zeroGradient),
# wall (slip), symmetryPlane, empty
ROLE_TYPE = {"inflow": "patch", "outflow": "patch", "wall": "wall",
             "symmetryPlane": "symmetryPlane", "empty": "empty"}


def patches_of(c):
    """{patch name: role} of a case."""
    if c["kind"] == "wedge":
        p = {"inlet": "inflow", "outlet": "outflow", "bottom": "symmetryPlane",
             "top": "symmetryPlane", "obstacle": "wall"}
        if c["mesher"] == "gmsh3d":
            p.update(sideBack="symmetryPlane", sideFront="symmetryPlane")
        else:
            p.update(frontAndBack="empty")
        return p
    if c["kind"] == "cone":
        return {"inlet": "inflow", "farfield": "inflow", "outlet": "outflow", "cone": "wall",
                "symmetryY": "symmetryPlane", "symmetryZ": "symmetryPlane"}
    if c["kind"] == "sphere":
        return {"inlet": "inflow", "outlet": "outflow", "sphere": "wall",
                "symmetryY": "symmetryPlane", "symmetryZ": "symmetryPlane"}
    return {"inlet": "inflow", "outlet": "outflow", "cylinder": "wall",
            "symmetry": "symmetryPlane", "frontAndBack": "empty"}


def lts_control(c, iterations=None, lts=LTS):
    """The controlDict entries of local time stepping (see LTS) for case c:
    deltaT 1, so that the time is the iteration count, `iterations` (default
    lts["iterations"]) of them, written every lts["write"], at the case's
    maxCo times lts["maxco"].  The payoff benchmark gives the adapted cases
    the same entries."""
    return dict(deltaT=1, endTime=lts["iterations"] if iterations is None else iterations,
                writeControl="timeStep", writeInterval=lts["write"], adjustTimeStep="no",
                maxCo="%g" % (c["maxco"] * lts["maxco"]), rDeltaTSmoothingCoeff="%g" % lts["smoothing"])


def write_case_files(case, c, lts=False):
    """constant/, system/ (without the mesh) and 0/; with `lts`, the
    controlDict and ddtSchemes of local time stepping (lts_control)."""
    write(os.path.join(case, "constant", "thermophysicalProperties"),
          header("dictionary", "thermophysicalProperties", "constant") + """
// normalised gas of the wedge15Ma5 tutorial: R = 8314.47 / 11640.3 = 1/1.4,
// Cp = 2.5, gamma = 1.4, speed of sound 1 at T = 1; inviscid (mu = 0)
thermoType
{
    type            hePsiThermo;
    mixture         pureMixture;
    transport       const;
    thermo          hConst;
    equationOfState perfectGas;
    specie          specie;
    energy          sensibleInternalEnergy;
}
mixture
{
    specie          { molWeight 11640.3; }
    thermodynamics  { Cp 2.5; Hf 0; }
    transport       { mu 0; Pr 1; }
}
""")
    write(os.path.join(case, "constant", "turbulenceProperties"),
          header("dictionary", "turbulenceProperties", "constant") + "simulationType  laminar;\n")
    u = "(%.12g 0 0)" % c["mach"]
    pat = patches_of(c)
    for name, cls, dims, value, wall in (("U", "volVectorField", "[0 1 -1 0 0 0 0]", u, "slip"),
                                          ("p", "volScalarField", "[1 -1 -2 0 0 0 0]", "1", "zeroGradient"),
                                          ("T", "volScalarField", "[0 0 0 1 0 0 0]", "1", "zeroGradient")):
        bcs = []
        for pname, role in pat.items():
            bc = {"inflow": "type fixedValue; value uniform %s;" % value,
                  "outflow": "type zeroGradient;",
                  "wall": "type %s;" % wall,
                  "symmetryPlane": "type symmetryPlane;",
                  "empty": "type empty;"}[role]
            bcs.append("    %-12s { %s }" % (pname, bc))
        write(os.path.join(case, "0", name), header(cls, name, "0")
              + "dimensions      %s;\ninternalField   uniform %s;\nboundaryField\n{\n%s\n}\n"
              % (dims, value, "\n".join(bcs)))
    if lts:
        # local time stepping (ddtSchemes localEuler): the time is the iteration count
        stepping = lts_control(c)
    else:
        stepping = {"endTime": "%g" % c["end"],
                    "deltaT": "1e-06",  # first step only: adjustTimeStep takes over
                    "writeControl": "adjustableRunTime", "writeInterval": "%g" % c["write"],
                    "adjustTimeStep": "yes", "maxCo": "%g" % c["maxco"]}
    write(os.path.join(case, "system", "controlDict"), header("dictionary", "controlDict", "system") + """
application     rhoCentralFoam;
startFrom       startTime;
startTime       0;
stopAt          endTime;
purgeWrite      0;
writeFormat     ascii;
writePrecision  8;
writeCompression off;
timeFormat      general;
timePrecision   6;
runTimeModifiable false;
maxDeltaT       1;
""" + "".join("%-15s %s;\n" % kv for kv in stepping.items()))
    if c["order"] == 2:
        recon = ("    reconstruct(rho) Minmod;\n    reconstruct(U)   MinmodV;\n"
                 "    reconstruct(T)   Minmod;\n")
    else:  # first order: no reconstruction, the face values are the upwind cells'
        recon = ("    reconstruct(rho) upwind;\n    reconstruct(U)   upwind;\n"
                 "    reconstruct(T)   upwind;\n")
    write(os.path.join(case, "system", "fvSchemes"), header("dictionary", "fvSchemes", "system") + """
fluxScheme      Tadmor;
ddtSchemes      { default %s; }
gradSchemes     { default %s; }
divSchemes      { default none; div(tauMC) Gauss linear; }
laplacianSchemes { default Gauss linear corrected; }
interpolationSchemes
{
    default          linear;
%s}
snGradSchemes   { default corrected; }
""" % ("localEuler" if lts else "Euler", c.get("grad", "Gauss linear"), recon))
    # the wedge15Ma5 tutorial's solver settings
    write(os.path.join(case, "system", "fvSolution"), header("dictionary", "fvSolution", "system") + """
solvers
{
    "(rho|rhoU|rhoE)" { solver diagonal; }
    U { solver smoothSolver; smoother GaussSeidel; nSweeps 2; tolerance 1e-09; relTol 0.01; }
    h { $U; tolerance 1e-10; relTol 0; }
}
""")


# ---------------------------------------------------------------------------- meshes
def blockmesh_wedge(c):
    """blockMeshDict of the 2-D wedge: two blocks as in the wedge15Ma5 tutorial, graded."""
    x0, x1, h, dz = c["x0"], c["x1"], c["height"], 0.5 * c["span"]
    y1 = x1 * math.tan(math.radians(c["angle"]))
    v2 = [(x0, 0), (0, 0), (x1, y1), (x0, h), (0, h), (x1, h)]
    verts = ["    (%.12g %.12g %.12g)" % (x, y, z) for z in (-dz, dz) for x, y in v2]
    nu, nd = c["nx"]
    gx, gy = c["grade_x"], c["grade_y"]
    return header("dictionary", "blockMeshDict", "system") + """
scale 1;
// tip of the wedge at the origin, ramp (obstacle) from (0 0) to (%g %g)
vertices
(
%s
);
blocks
(
    // x: cells shrink towards the tip by %g in each block; y: towards the wall by %g
    hex (0 1 4 3 6 7 10 9)  (%d %d 1) simpleGrading (%.12g %.12g 1)
    hex (1 2 5 4 7 8 11 10) (%d %d 1) simpleGrading (%.12g %.12g 1)
);
edges ();
boundary
(
    inlet    { type patch; faces ((0 6 9 3)); }
    outlet   { type patch; faces ((2 5 11 8)); }
    bottom   { type symmetryPlane; faces ((0 1 7 6)); }
    top      { type symmetryPlane; faces ((3 9 10 4) (4 10 11 5)); }
    obstacle { type wall; faces ((1 2 8 7)); }
    frontAndBack { type empty; faces ((0 3 4 1) (1 4 5 2) (6 7 10 9) (7 8 11 10)); }
);
mergePatchPairs ();
""" % (x1, y1, "\n".join(verts), gx, gy, nu, c["ny"], 1.0 / gx, gy, nd, c["ny"], gx, gy)


def cylinder_outer(c, phis):
    """Points (x, y) of the inflow boundary on the rays from the centre at the
    angles phis (pi: the axis upstream .. pi/2: the plane x = 0): Billig's shock
    moved upstream by margin(y) = m0 + m1 y."""
    m0, m1 = c["margin"]
    r, mach = c["radius"], c["mach"]

    def outside(x, y):
        return x < billig_shock_x(y, mach, r) - (m0 + m1 * y)
    pts = []
    for phi in phis:
        lo, hi = r, 50.0 * r                             # distance along the ray
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if outside(mid * math.cos(phi), mid * math.sin(phi)):
                hi = mid
            else:
                lo = mid
        d = 0.5 * (lo + hi)
        pts.append((d * math.cos(phi), d * math.sin(phi)))
    return pts


def blockmesh_cylinder(c):
    """blockMeshDict of the half cylinder: nb blocks side by side along the body,
    each between two rays from the centre, so that the mesh lines off the body
    are nearly radial (normal to the wall)."""
    r, dz = c["radius"], 0.5 * c["span"]
    nb = c["blocks"]
    sub = 8                                              # spline points per block edge
    phis = [math.pi - 0.5 * math.pi * k / nb for k in range(nb + 1)]
    outer = cylinder_outer(c, phis)
    outer[0], outer[-1] = (outer[0][0], 0.0), (0.0, outer[-1][1])   # exactly on y = 0, x = 0
    body = [(r * math.cos(f), r * math.sin(f)) for f in phis]
    body[0], body[-1] = (-r, 0.0), (0.0, r)
    v2 = body + outer                                    # body k: k, outer k: nb + 1 + k
    n2 = len(v2)
    # z = +dz first, then z = -dz (right-handed: x1 off the body, x2 along it)
    verts = ["    (%.12g %.12g %.12g)  // %d" % (x, y, z, i + n2 * j)
             for j, z in enumerate((dz, -dz)) for i, (x, y) in enumerate(v2)]

    def b(k, back=0):
        return k + n2 * back

    def o(k, back=0):
        return nb + 1 + k + n2 * back
    n_along = c["n_along"] // nb
    blocks, edges = [], []
    for k in range(nb):
        blocks.append("    hex (%d %d %d %d %d %d %d %d) (%d %d 1) simpleGrading (%.12g 1 1)"
                      % (b(k), o(k), o(k + 1), b(k + 1), b(k, 1), o(k, 1), o(k + 1, 1), b(k + 1, 1),
                         c["n_normal"], n_along, c["grade_normal"]))
        fm = 0.5 * (phis[k] + phis[k + 1])
        inner = cylinder_outer(c, [phis[k] + (phis[k + 1] - phis[k]) * i / sub for i in range(1, sub)])
        for back, z in ((0, dz), (1, -dz)):
            edges.append("    arc %d %d (%.12g %.12g %.12g)" % (b(k, back), b(k + 1, back),
                                                               r * math.cos(fm), r * math.sin(fm), z))
            edges.append("    spline %d %d (%s)" % (o(k, back), o(k + 1, back),
                                                   " ".join("(%.12g %.12g %.12g)" % (x, y, z) for x, y in inner)))

    def faces(quads):
        return " ".join("(%d %d %d %d)" % q for q in quads)
    return header("dictionary", "blockMeshDict", "system") + """
scale 1;
// cylinder of radius %g centred at the origin; inflow boundary: Billig's bow
// shock moved upstream by the margin, from (%.6g 0) to (0 %.6g)
vertices
(
%s
);
blocks
(
    // x1 off the body (cells grow by %g from the body to the inflow boundary), x2 along it
%s
);
edges
(
%s
);
boundary
(
    inlet    { type patch; faces (%s); }
    outlet   { type patch; faces (%s); }
    cylinder { type wall; faces (%s); }
    symmetry { type symmetryPlane; faces (%s); }
    frontAndBack { type empty; faces (%s); }
);
mergePatchPairs ();
""" % (r, outer[0][0], outer[-1][1], "\n".join(verts), c["grade_normal"], "\n".join(blocks), "\n".join(edges),
       faces([(o(k), o(k, 1), o(k + 1, 1), o(k + 1)) for k in range(nb)]),
       faces([(o(nb), o(nb, 1), b(nb, 1), b(nb))]),
       faces([(b(k), b(k + 1), b(k + 1, 1), b(k, 1)) for k in range(nb)]),
       faces([(b(0), b(0, 1), o(0, 1), o(0))]),
       faces([(b(k), o(k), o(k + 1), b(k + 1)) for k in range(nb)]
             + [(b(k, 1), b(k + 1, 1), o(k + 1, 1), o(k, 1)) for k in range(nb)]))


def gmsh_wedge(c):
    """Gmsh .geo of the wedge cross-section (z = -span/2), extruded by the span:
    one layer of prisms (gmsh2d) or a volume of tetrahedra (gmsh3d)."""
    t = math.radians(c["angle"])
    layers = "Layers{1}; Recombine;" if c["mesher"] == "gmsh2d" else ""
    names = ("frontAndBack", "frontAndBack") if c["mesher"] == "gmsh2d" else ("sideBack", "sideFront")
    groups = ('Physical Surface("%s") = {1, ext[0]};' % names[0] if names[0] == names[1] else
              'Physical Surface("%s") = {1};\nPhysical Surface("%s") = {ext[0]};' % names)
    return """// wedge cross-section: tip at the origin, ramp at %g deg to x = %g
x0 = %.12g; x1 = %.12g; H = %.12g; z0 = %.12g; W = %.12g;
ct = %.15g; st = %.15g;
Point(1) = {x0, 0, z0};
Point(2) = {0, 0, z0};
Point(3) = {x1, x1*st/ct, z0};
Point(4) = {x1, H, z0};
Point(5) = {x0, H, z0};
Line(1) = {1, 2};   // bottom (symmetry plane upstream of the tip)
Line(2) = {2, 3};   // obstacle (the ramp)
Line(3) = {3, 4};   // outlet
Line(4) = {4, 5};   // top (symmetry plane)
Line(5) = {5, 1};   // inlet
Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};
// size: hmin at the wall and the tip, growing linearly with the distance d
// from them (d from the tip upstream of it, from the ramp's line above it)
// to hmax at d = dgrow
hmin = %g; hmax = %g; dgrow = %g;
Field[1] = MathEval;
Field[1].F = Sprintf("Min(%%g, %%g + %%g*Sqrt(Max(0,-x)^2 + Max(0, y*%%.15g - Max(0,x)*%%.15g)^2))",
                     hmax, hmin, (hmax - hmin)/dgrow, ct, st);
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm = 6;       // Frontal-Delaunay triangles
Mesh.Algorithm3D = 1;     // Delaunay tetrahedra (deterministic with one thread)
Mesh.Optimize = 1;
Mesh.OptimizeThreshold = 0.6;
ext[] = Extrude {0, 0, W} { Surface{1}; %s };
// ext[0]: the far side (z = z0 + W), ext[1]: the volume, ext[2..6]: from lines 1..5
Physical Surface("bottom") = {ext[2]};
Physical Surface("obstacle") = {ext[3]};
Physical Surface("outlet") = {ext[4]};
Physical Surface("top") = {ext[5]};
Physical Surface("inlet") = {ext[6]};
%s
Physical Volume("fluid") = {ext[1]};
""" % (c["angle"], c["x1"], c["x0"], c["x1"], c["height"], -0.5 * c["span"], c["span"],
       math.cos(t), math.sin(t), c["hmin"], c["hmax"], c["dgrow"], layers, groups)


# The Gmsh options of the 3-D meshes (the size from the background field
# alone; deterministic with one thread).
GMSH_VOLUME_OPTIONS = """Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm = 6;       // Frontal-Delaunay surfaces
Mesh.Algorithm3D = 1;     // Delaunay volume (deterministic with one thread)
Mesh.Optimize = 1;
Mesh.OptimizeThreshold = 0.6;   // fewer slivers: a larger stable time step
"""


def gmsh_cone(c):
    """Gmsh .geo of the quarter domain around the cone (as Data/make_cone20Ma2p5.sh)."""
    return """// Quarter domain (y >= 0, z >= 0) around a sharp %g deg cone, tip at the origin, axis +x.
SetFactory("OpenCASCADE");
x0 = %.12g; x1 = %.12g; R = %.12g;   // inlet plane, outlet plane, side radius
a = %.15g*Pi/180;                     // cone half-angle
Cylinder(1) = {x0, 0, 0, x1 - x0, 0, 0, R};
Box(2) = {x0 - 1, 0, 0, x1 - x0 + 2, R + 1, R + 1};
BooleanIntersection(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };
Cone(4) = {0, 0, 0, 1.2*x1, 0, 0, 0, 1.2*x1*Tan(a)};                 // longer than the domain
BooleanDifference(5) = { Volume{3}; Delete; }{ Volume{4}; Delete; };

e = 1e-6;
sIn() = Surface In BoundingBox{x0 - e, -e, -e, x0 + e, R + e, R + e};
sOut() = Surface In BoundingBox{x1 - e, -e, -e, x1 + e, R + e, R + e};
sSymY() = Surface In BoundingBox{x0 - e, -e, -e, x1 + e, e, R + e};
sSymZ() = Surface In BoundingBox{x0 - e, -e, -e, x1 + e, R + e, e};
sCone() = Surface In BoundingBox{-e, -e, -e, x1 + e, x1*Tan(a) + e, x1*Tan(a) + e};
sFar() = Surface{:};
sFar() -= {sIn(), sOut(), sSymY(), sSymZ(), sCone()};
If (#sIn() != 1 || #sOut() != 1 || #sSymY() != 1 || #sSymZ() != 1 || #sCone() < 1 || #sFar() < 1)
  Error("unexpected boundary surfaces: in %%g out %%g symY %%g symZ %%g cone %%g far %%g",
        #sIn(), #sOut(), #sSymY(), #sSymZ(), #sCone(), #sFar());
  Abort;
EndIf
Physical Surface("inlet") = {sIn()};
Physical Surface("outlet") = {sOut()};
Physical Surface("farfield") = {sFar()};
Physical Surface("cone") = {sCone()};
Physical Surface("symmetryY") = {sSymY()};
Physical Surface("symmetryZ") = {sSymZ()};
Physical Volume("fluid") = {5};

// size field: h0 + h1 rho in the band pa <= phi <= pb of polar angles from the
// axis (the cone surface, the conical flow and the shock), rho = the distance
// from the tip; growing by grow * rho * (angle outside the band, rad); at most hc
hf0 = %g; hf1 = %g; grow = %g; hc = %g;
pa = %g*Pi/180; pb = %g*Pi/180;
Field[1] = MathEval;
Field[1].F = Sprintf(StrCat("%%g + %%g*Sqrt(x*x+y*y+z*z) + %%g*Sqrt(x*x+y*y+z*z)*",
                            "(Max(0, %%g - Acos(x/(Sqrt(x*x+y*y+z*z)+1e-12)))",
                            " + Max(0, Acos(x/(Sqrt(x*x+y*y+z*z)+1e-12)) - %%g))"),
                     hf0, hf1, grow, pa, pb);
Field[2] = MathEval;
Field[2].F = Sprintf("%%g", hc);
Field[3] = Min;
Field[3].FieldsList = {1, 2};
Background Field = 3;
""" % (c["angle"], c["x0"], c["x1"], c["radius"], c["angle"], c["h0"], c["h1"], c["grow"],
       c["hmax"], c["band"][0], c["band"][1]) + GMSH_VOLUME_OPTIONS


def gmsh_sphere(c):
    """Gmsh .geo of the quarter of the front half of the domain around a sphere."""
    xc, ro = c["outer"]
    return """// Quarter domain (y >= 0, z >= 0), front half (x <= 0: the outlet plane, where
// the flow is supersonic) around a sphere of radius R at the origin; the inflow
// boundary: a sphere of radius Ro about (xc, 0, 0), 0.15 or more upstream of
// Billig's bow shock.
SetFactory("OpenCASCADE");
R = %.12g; xc = %.12g; Ro = %.12g;
Sphere(1) = {xc, 0, 0, Ro};
Box(2) = {xc - Ro - 1, 0, 0, Ro - xc + 1, Ro + 1, Ro + 1};
BooleanIntersection(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };
Sphere(4) = {0, 0, 0, R};
BooleanDifference(5) = { Volume{3}; Delete; }{ Volume{4}; Delete; };

e = 1e-6; B = Ro + 1;
sOut() = Surface In BoundingBox{-e, -e, -e, e, B, B};
sSymY() = Surface In BoundingBox{-B, -e, -e, e, e, B};
sSymZ() = Surface In BoundingBox{-B, -e, -e, e, B, e};
sBody() = Surface In BoundingBox{-R - e, -e, -e, e, R + e, R + e};
sBody() -= {sOut(), sSymY(), sSymZ()};
sIn() = Surface{:};
sIn() -= {sOut(), sSymY(), sSymZ(), sBody()};
If (#sOut() != 1 || #sSymY() != 1 || #sSymZ() != 1 || #sBody() != 1 || #sIn() != 1)
  Error("unexpected boundary surfaces: out %%g symY %%g symZ %%g body %%g in %%g",
        #sOut(), #sSymY(), #sSymZ(), #sBody(), #sIn());
  Abort;
EndIf
Physical Surface("inlet") = {sIn()};
Physical Surface("outlet") = {sOut()};
Physical Surface("sphere") = {sBody()};
Physical Surface("symmetryY") = {sSymY()};
Physical Surface("symmetryZ") = {sSymZ()};
Physical Volume("fluid") = {5};

// size: hmin at the wall, growing linearly with the distance from it to hmax
// at dgrow (nothing finer at the shock)
hmin = %g; hmax = %g; dgrow = %g;
Field[1] = MathEval;
Field[1].F = Sprintf("Min(%%g, %%g + %%g*Max(0, Sqrt(x*x+y*y+z*z) - %%g))",
                     hmax, hmin, (hmax - hmin)/dgrow, R);
Background Field = 1;
""" % (c["radius"], xc, ro, c["hmin"], c["hmax"], c["dgrow"]) + GMSH_VOLUME_OPTIONS


def fix_boundary(path, want):
    """Patch types in constant/polyMesh/boundary after gmshToFoam (which makes
    every physical surface a plain patch)."""
    with open(path) as f:
        txt = f.read()
    found = set()

    def fix(m):
        name, body = m.group(1), m.group(2)
        if name == "FoamFile":
            return m.group(0)
        found.add(name)
        if name not in want:
            return m.group(0)
        body = re.sub(r"\btype\s+\w+\s*;", "type            %s;" % want[name], body)
        body = re.sub(r"\s*physicalType\s+\w+\s*;", "", body)
        body = re.sub(r"\s*inGroups\s+[^;]*;", "", body)
        return "%s\n    {%s}" % (name, body)
    txt = re.sub(r"\b(\w+)\s*\{([^{}]*)\}", fix, txt)
    if found != set(want):
        raise RuntimeError("boundary: missing patches %s, unexpected patches %s"
                           % (sorted(set(want) - found), sorted(found - set(want))))
    with open(path, "w") as f:
        f.write(txt)


# ---------------------------------------------------------------------------- running
def foam_environment():
    """os.environ plus what OpenFOAM's bashrc sets."""
    if not os.path.isfile(FOAM_BASHRC):
        sys.exit("missing %s (apt-get install openfoam)" % FOAM_BASHRC)
    out = subprocess.run(["bash", "-c", 'source "%s" >/dev/null 2>&1; env -0' % FOAM_BASHRC],
                         check=True, stdout=subprocess.PIPE).stdout
    env = dict(kv.split("=", 1) for kv in out.decode().split("\0") if "=" in kv)
    for prog in ("blockMesh", "gmshToFoam", "checkMesh", "rhoCentralFoam"):
        if shutil.which(prog, path=env.get("PATH")) is None:
            sys.exit("OpenFOAM environment not set up: no %s" % prog)
    return env


def run(name, cmd, cwd, logfile, env=None):
    if env is not None:
        env = dict(env, PWD=cwd)     # else OpenFOAM warns that PWD is not the cwd
    with open(os.path.join(cwd, logfile), "w") as f:
        r = subprocess.run(cmd, cwd=cwd, env=env, stdout=f, stderr=subprocess.STDOUT)
    if r.returncode != 0:
        with open(os.path.join(cwd, logfile)) as f:
            tail = f.read()[-3000:]
        raise RuntimeError("%s failed (%s, exit %d):\n%s" % (cmd[0], logfile, r.returncode, tail))


def read_p(case, t):
    with open(os.path.join(case, t, "p")) as f:
        txt = f.read()
    m = re.search(r"internalField\s+nonuniform\s+List<scalar>\s*(\d+)\s*\(", txt)
    if not m:
        raise RuntimeError("cannot parse %s/p" % t)
    v = [float(x) for x in txt[m.end():].split(")", 1)[0].split()]
    if len(v) != int(m.group(1)):
        raise RuntimeError("%s/p: expected %s values, got %d" % (t, m.group(1), len(v)))
    return v


def time_dirs(case):
    return sorted((d for d in os.listdir(case) if re.fullmatch(r"[0-9.eE+-]+", d)
                   and float(d) > 0 and os.path.isfile(os.path.join(case, d, "p"))), key=float)


def steadiness(case):
    """(rms dp / range, max|dp| / range, range, t_a, t_b) over the last two writes."""
    times = time_dirs(case)
    if len(times) < 2:
        raise RuntimeError("not enough time steps written: %s" % times)
    a, b = read_p(case, times[-2]), read_p(case, times[-1])
    d = [abs(x - y) for x, y in zip(a, b)]
    rng = max(b) - min(b)
    rms = (sum(x * x for x in d) / len(d)) ** 0.5
    return rms / rng, max(d) / rng, rng, times[-2], times[-1]


def solver_history(case, log="log.rhoCentralFoam"):
    """[(time, ExecutionTime s, ClockTime s)] of each step in the solver's log."""
    out, t = [], None
    with open(os.path.join(case, log)) as f:
        for line in f:
            if line.startswith("Time = "):
                t = float(line.split()[2])
            elif line.startswith("ExecutionTime = ") and t is not None:
                w = line.split()
                out.append((t, float(w[2]), float(w[6])))
    return out


def steady_time(case, tol=STEADY_RMS, log="log.rhoCentralFoam"):
    """When the solution became steady: the first written time from which
    on every change of p between consecutive writes stays below `tol` of
    the p range (rms), with the solver's CPU and clock seconds to reach it
    (from its log).  Returns (time, cpu s, clock s, [(t, rms/range)]), the
    time None if it never settled."""
    times = time_dirs(case)
    changes, prev = [], None
    for t in times:
        p = read_p(case, t)
        if prev is not None:
            d = [x - y for x, y in zip(p, prev)]
            changes.append((float(t), (sum(x * x for x in d) / len(d)) ** 0.5 / (max(p) - min(p))))
        prev = p
    settled = None
    for i in range(len(changes) - 1, -1, -1):
        if changes[i][1] >= tol:
            break
        settled = changes[i][0]
    # the write before the first small change is where the solution already
    # was what it stays: the steady time is that earlier write
    if settled is not None:
        k = [c[0] for c in changes].index(settled)
        settled = changes[k - 1][0] if k > 0 else float(times[0])
    history = solver_history(case, log)
    if settled is None or not history:
        return None, None, None, changes
    step = min(history, key=lambda h: abs(h[0] - settled))
    return settled, step[1], step[2], changes


def check_mesh_summary(case):
    with open(os.path.join(case, "log.checkMesh")) as f:
        txt = f.read()
    if "Mesh OK" not in txt:
        bad = "\n".join(l for l in txt.splitlines() if "***" in l or "fail" in l.lower())
        raise RuntimeError("checkMesh failed:\n%s" % bad)
    cells = int(re.search(r"^\s*cells:\s+(\d+)", txt, re.M).group(1))
    kinds = {k: int(n) for k, n in re.findall(r"^\s*(hexahedra|prisms|wedges|pyramids|tet wedges|"
                                                r"tetrahedra|polyhedra):\s+(\d+)", txt, re.M) if int(n)}
    return cells, kinds


def prepare_dir(keep):
    if keep is None:
        return tempfile.mkdtemp(prefix="validation.", dir=os.environ.get("TMPDIR", "/tmp")), False
    keep = os.path.abspath(keep)
    if os.path.isdir(keep) and os.listdir(keep):
        if not os.path.exists(os.path.join(keep, MARKER)):
            sys.exit("--keep %s: not empty and not made by this script" % keep)
        shutil.rmtree(keep)
    os.makedirs(keep, exist_ok=True)
    return keep, True


def refined(c, factor):
    """The case with its mesh refined uniformly by `factor` (> 0; 1 is the
    case itself): blockMesh cell counts times `factor` (rounded), Gmsh sizes
    divided by it; the grading, the geometry and the solver settings stay.
    The payoff benchmark (Testing/Benchmark/bench_payoff.py) uses it for the
    uniform meshes that bracket an adapted mesh's node count."""
    if not factor > 0:
        raise ValueError("--refine must be positive (got %r)" % factor)
    c = dict(c)
    n = lambda k: max(1, int(round(k * factor)))
    for key in ("ny", "n_normal", "n_along"):
        if key in c:
            c[key] = n(c[key])
    if "nx" in c:
        c["nx"] = tuple(n(k) for k in c["nx"])
    for key in ("hmin", "hmax", "h0", "h1", "grow"):
        if key in c:
            c[key] = c[key] / factor
    return c


def make(name, out, keep_dir, refine=1.0, lts=False):
    c = refined(CASES[name], refine)
    for prog in ("pvpython",) + (("gmsh",) if c["mesher"].startswith("gmsh") else ()):
        if shutil.which(prog) is None:
            sys.exit("%s not found (apt-get install %s)" % (prog, {"pvpython": "paraview python3-paraview"}
                                                            .get(prog, prog)))
    env = foam_environment()
    work, keep = prepare_dir(keep_dir)
    case = os.path.join(work, name) if not keep else work
    os.makedirs(case, exist_ok=True)
    open(os.path.join(work, MARKER), "w").close()
    t0 = time.time()
    ok = False
    try:
        _, _, summary = theory(c)
        log(name, "%s, order %d; theory: %s" % (c["kind"], c["order"], summary))
        write_case_files(case, c, lts)
        if c["mesher"] == "blockMesh":
            write(os.path.join(case, "system", "blockMeshDict"),
                  blockmesh_wedge(c) if c["kind"] == "wedge" else blockmesh_cylinder(c))
            log(name, "blockMesh")
            run(name, ["blockMesh"], case, "log.blockMesh", env)
        else:
            geo = os.path.join(case, name + ".geo")
            write(geo, {"wedge": gmsh_wedge, "cone": gmsh_cone, "sphere": gmsh_sphere}[c["kind"]](c))
            log(name, "gmsh")
            run(name, ["gmsh", "-3", "-format", "msh2", "-nt", "1", geo, "-o", name + ".msh"],
                case, "log.gmsh")
            with open(os.path.join(case, "log.gmsh")) as f:
                errors = [l for l in f if l.startswith("Error")]
            if errors:
                raise RuntimeError("gmsh: %s" % "".join(errors))
            run(name, ["gmshToFoam", name + ".msh"], case, "log.gmshToFoam", env)
            fix_boundary(os.path.join(case, "constant", "polyMesh", "boundary"),
                         {p: ROLE_TYPE[r] for p, r in patches_of(c).items()})
        with open(os.path.join(case, "log.checkMesh"), "w") as f:   # its exit status says nothing
            subprocess.run(["checkMesh"], cwd=case, env=dict(env, PWD=case), stdout=f, stderr=subprocess.STDOUT)
        cells, kinds = check_mesh_summary(case)
        log(name, "mesh: %d cells (%s)" % (cells, ", ".join("%d %s" % (n, k) for k, n in kinds.items())))

        if lts:
            log(name, "rhoCentralFoam, serial, local time stepping (%(endTime)d iterations, written every "
                "%(writeInterval)d, maxCo %(maxCo)s, rDeltaTSmoothingCoeff %(rDeltaTSmoothingCoeff)s)"
                % lts_control(c))
        else:
            log(name, "rhoCentralFoam, serial (endTime %g, writeInterval %g, maxCo %g)"
                % (c["end"], c["write"], c["maxco"]))
        t1 = time.time()
        run(name, ["rhoCentralFoam"], case, "log.rhoCentralFoam", env)
        wall = time.time() - t1
        with open(os.path.join(case, "log.rhoCentralFoam")) as f:
            txt = f.read()
        steps = len(re.findall(r"^Time = ", txt, re.M))
        co = re.findall(r"Mean and max Courant Numbers = (\S+) (\S+)", txt)
        if not re.search(r"^End", txt, re.M):
            raise RuntimeError("rhoCentralFoam did not finish")
        log(name, "solver wall time %.1f s (%d steps, %.2f ms/step; last max Courant %s)"
            % (wall, steps, 1e3 * wall / max(1, steps), co[-1][1] if co else "?"))
        rms, dmax, rng, ta, tb = steadiness(case)
        log(name, "steadiness: p(t=%s) vs p(t=%s): rms dp = %.3g%% of the p range %.4g, max|dp| = %.3g%%"
            % (ta, tb, 100 * rms, rng, 100 * dmax))
        if rms > STEADY_RMS:
            raise RuntimeError("NOT steady (rms dp over %g%% of the p range)" % (100 * STEADY_RMS))

        log(name, "converting t = %s to %s" % (tb, out))
        args = dict(name=name, case=case, out=out, rms=rms, dmax=dmax, wall=wall, cells=cells,
                    kinds=kinds)
        r = subprocess.run(["pvpython", os.path.abspath(__file__), "--convert", json.dumps(args)])
        if r.returncode != 0:
            raise RuntimeError("conversion / physics check failed (exit %d)" % r.returncode)
        ok = True
        log(name, "done in %.0f s: %s (%d bytes); %d cells (%s), solver %.1f s, rms dp %.3g%%; %s"
            % (time.time() - t0, out, os.path.getsize(out), cells,
               ", ".join("%d %s" % (n, k) for k, n in kinds.items()), wall, 100 * rms, summary))
    except RuntimeError as e:
        print("[%s] FAILED: %s" % (name, e), file=sys.stderr)
    finally:
        if keep or not ok:
            log(name, "case kept in %s" % case)
        else:
            shutil.rmtree(work, ignore_errors=True)
    return 0 if ok else 1


# ---------------------------------------------------------------------------- conversion (pvpython)
def convert(args):
    """Runs under pvpython: the .vtu with its field data, and the physics check."""
    import numpy as np
    import foam_vtu
    from convert_cone20Ma2p5 import probe_p
    from paraview import servermanager, simple
    from vtkmodules.util import numpy_support as nps
    from vtkmodules.vtkCommonDataModel import VTK_HEXAHEDRON, VTK_TETRA, VTK_WEDGE

    name, case, out = args["name"], args["case"], args["out"]
    c = CASES[name]
    cell_type, cell_name = {"blockMesh": (VTK_HEXAHEDRON, "hexahedra"), "gmsh2d": (VTK_WEDGE, "wedges"),
                            "gmsh3d": (VTK_TETRA, "tetrahedra")}[c["mesher"]]
    src, time_dir, t_last = foam_vtu.read_last_time(case, cell_type, cell_name)
    gamma, r_gas, cp, mol_weight = foam_case.gas_properties(case)
    u_in, t_in, p_in = foam_case.inlet_state(case, time_dir)
    mach = math.sqrt(sum(x * x for x in u_in)) / math.sqrt(gamma * r_gas * t_in)
    flow = np.asarray(u_in, dtype=np.float64) / np.linalg.norm(u_in)

    def patch_points(patch):
        rd = simple.OpenFOAMReader(FileName=foam_vtu.foam_file(case))
        rd.MeshRegions = ["patch/" + patch]
        rd.CellArrays = []
        rd.SkipZeroTime = 1
        m = simple.MergeBlocks(Input=rd)
        m.UpdatePipeline(t_last)
        pts = servermanager.Fetch(m)
        if pts is None or pts.GetNumberOfPoints() < 4:
            sys.exit("no points on patch '%s'" % patch)
        return nps.vtk_to_numpy(pts.GetPoints().GetData()).astype(np.float64)

    def shock_angle(grid, tip, axis, normals, half_angle, length, p_mid):
        """Shock angle (deg) on each plane (axis, normal): a line through the tip
        fitted to the outermost p = p_mid crossings at 12 stations."""
        pts = nps.vtk_to_numpy(grid.GetPoints().GetData()).astype(np.float64) - tip
        rmax = np.abs(pts @ np.array(normals).T).max()
        tan_b = math.tan(math.radians(half_angle))
        res = []
        for d in normals:
            xs, rs = [], []
            for x in np.linspace(0.15, 0.9, 12) * length:
                r = last_crossing(grid, tip + x * axis, d, x * tan_b * 1.001 + 1e-9, rmax, p_mid)
                if r is not None:
                    xs.append(x)
                    rs.append(r)
            if len(xs) < 5:
                sys.exit("shock not found on the plane normal %s" % (d,))
            xs, rs = np.array(xs), np.array(rs)
            local = np.degrees(np.arctan2(rs, xs))
            res.append((math.degrees(math.atan((xs @ rs) / (xs @ xs))), local.min(), local.max(), len(xs)))
        return res

    fields = [("Gamma", (gamma,)), ("GasConstant", (r_gas,)), ("UpstreamMach", (mach,)),
              ("FlowDirection", flow), ("SchemeOrder", (c["order"],))]
    lines = []
    if c["kind"] == "wedge":
        pts = patch_points("obstacle")
        tip2 = pts[np.argmin(pts[:, 0]), :2]
        d = pts[:, :2] - tip2
        far = np.linalg.norm(d, axis=1) > 1e-9
        ang = np.degrees(np.arctan2(d[far, 1], d[far, 0]))
        wedge = float(np.mean(ang))
        if np.abs(ang - c["angle"]).max() > 1e-4 or np.abs(tip2).max() > 1e-9:
            sys.exit("patch 'obstacle' is not the ramp at %g deg from the origin (%.6g .. %.6g deg, tip %s)"
                     % (c["angle"], ang.min(), ang.max(), tip2))
        zmid = 0.5 * (pts[:, 2].min() + pts[:, 2].max())
        tip = np.array([tip2[0], tip2[1], zmid])
        beta = theta_beta_mach.shock_angle(mach, wedge, gamma)
        jump = theta_beta_mach.oblique_shock_jump(mach, beta, gamma)
        b = math.radians(beta)
        fields += [("WedgeAngle", (wedge,)), ("WedgeTip", tip), ("WedgeSpan", (0.0, 0.0, 1.0)),
                   ("ShockAngleThetaBetaMach", (beta,)), ("ShockNormal", (math.sin(b), -math.cos(b), 0.0)),
                   ("ShockPressureRatio", (jump.p2_p1,))]
        lines.append("wedge       angle %.6f deg (obstacle points within %.2g deg), tip (%g, %g, %g)"
                     % ((wedge, np.abs(ang - wedge).max()) + tuple(tip)))
        lines.append("shock       theta-beta-Mach beta = %.4f deg, p2/p1 = %.4f" % (beta, jump.p2_p1))
        p_mid = 0.5 * p_in * (1.0 + jump.p2_p1)
        want = beta
    elif c["kind"] == "cone":
        from convert_cone20Ma2p5 import cone_geometry
        half, tip, axis, dev = cone_geometry(patch_points("cone"), u_in)
        if dev > 0.05 or abs(half - c["angle"]) > 0.05 or np.linalg.norm(tip) > 1e-6:
            sys.exit("patch 'cone' is not the %g deg cone at the origin (%.4f deg, within %.3g deg, tip %s)"
                     % (c["angle"], half, dev, tip))
        if math.degrees(math.acos(min(1.0, abs(float(axis @ flow))))) > 0.01:
            sys.exit("the inflow is not along the cone axis %s" % (axis,))
        tm = taylor_maccoll.taylor_maccoll(mach, half, gamma)
        fields += [("ConeHalfAngle", (half,)), ("ConeTip", tip), ("ConeAxis", axis),
                   ("ShockAngleTaylorMaccoll", (tm.shock_angle,)),
                   ("ConePressureRatioTaylorMaccoll", (tm.cone_p_p1,)),
                   ("ShockPressureRatioTaylorMaccoll", (tm.shock_p2_p1,))]
        lines.append("cone        half-angle %.6f deg (points within %.2g deg), tip (%.3g, %.3g, %.3g), "
                     "axis (%.6f, %.6f, %.6f)" % ((half, dev) + tuple(tip) + tuple(axis)))
        lines.append("shock       Taylor-Maccoll beta = %.4f deg; cone surface p/p1 = %.4f; p2/p1 = %.4f"
                     % (tm.shock_angle, tm.cone_p_p1, tm.shock_p2_p1))
        p_mid = 0.5 * p_in * (1.0 + tm.shock_p2_p1)
        want = tm.shock_angle
    elif c["kind"] == "sphere":
        pts = patch_points("sphere")
        A = np.c_[2 * pts, np.ones(len(pts))]
        sol = np.linalg.lstsq(A, (pts ** 2).sum(axis=1), rcond=None)[0]
        centre = sol[:3]
        rad = float(np.sqrt(sol[3] + centre @ centre))
        dev = np.abs(np.linalg.norm(pts - centre, axis=1) - rad).max()
        # Gmsh's wall points lie on the sphere, its triangles inside it: the
        # points within float32 of it
        if dev > 1e-6 or abs(rad - c["radius"]) > 1e-6 or np.abs(centre).max() > 1e-6:
            sys.exit("patch 'sphere' is not the sphere r = %g about the origin (r %.8g, centre %s, dev %.3g)"
                     % (c["radius"], rad, centre, dev))
        centre, rad = np.zeros(3), float(c["radius"])
        p21 = theta_beta_mach.oblique_shock_jump(mach, 90.0, gamma).p2_p1
        pitot = pitot_ratio(mach, gamma)
        standoff_b = billig_sphere(mach, rad)[0]
        fields += [("SphereCentre", centre), ("SphereRadius", (rad,)),
                   ("NormalShockPressureRatio", (p21,)), ("StagnationPressureRatio", (pitot,)),
                   ("ShockStandoffBillig", (standoff_b,))]
        lines.append("sphere      centre (%g, %g, %g), radius %.8g (wall points within %.2g)"
                     % (tuple(centre) + (rad, dev)))
        lines.append("shock       normal shock p2/p1 = %.4f, pitot p0'/p1 = %.4f, Billig standoff %.4f"
                     % (p21, pitot, standoff_b))
    else:
        pts = patch_points("cylinder")
        # centre: least-squares circle through the (x, y) of the wall points
        A = np.c_[2 * pts[:, 0], 2 * pts[:, 1], np.ones(len(pts))]
        sol = np.linalg.lstsq(A, (pts[:, :2] ** 2).sum(axis=1), rcond=None)[0]
        centre2 = sol[:2]
        rad = float(np.sqrt(sol[2] + centre2 @ centre2))
        dev = np.abs(np.linalg.norm(pts[:, :2] - centre2, axis=1) - rad).max()
        if dev > 1e-6 or abs(rad - c["radius"]) > 1e-6 or np.abs(centre2).max() > 1e-6:
            sys.exit("patch 'cylinder' is not the circle r = %g about the origin (r %.8g, centre %s, dev %.3g)"
                     % (c["radius"], rad, centre2, dev))
        # stored: the nominal centre and radius, which the fit has just confirmed
        # (it scatters by ~3e-9 from the float32 points)
        centre = np.array([0.0, 0.0, 0.5 * (pts[:, 2].min() + pts[:, 2].max())])
        rad = float(c["radius"])
        p21 = theta_beta_mach.oblique_shock_jump(mach, 90.0, gamma).p2_p1
        pitot = pitot_ratio(mach, gamma)
        standoff_b = billig(mach, rad)[0]
        fields += [("CylinderCentre", centre), ("CylinderRadius", (rad,)), ("CylinderAxis", (0.0, 0.0, 1.0)),
                   ("NormalShockPressureRatio", (p21,)), ("StagnationPressureRatio", (pitot,)),
                   ("ShockStandoffBillig", (standoff_b,))]
        lines.append("cylinder    centre (%g, %g, %g), radius %.8g (wall points within %.2g)"
                     % (tuple(centre) + (rad, dev)))
        lines.append("shock       normal shock p2/p1 = %.4f, pitot p0'/p1 = %.4f, Billig standoff %.4f"
                     % (p21, pitot, standoff_b))
    fields += [("SteadinessRmsDp", (args["rms"],)), ("SteadinessMaxDp", (args["dmax"],)),
               ("SolutionTime", (t_last,))]

    grid = foam_vtu.flow_grid(src, gamma)
    for fname, values in fields:
        foam_vtu.add_field(grid, fname, values)
    back = foam_vtu.write_and_check(grid, out, cell_type)
    print("case        %s (time %s)" % (case, time_dir))
    print("gas         Cp %g, molWeight %g -> R %.6g, gamma %.6g" % (cp, mol_weight, r_gas, gamma))
    print("inlet       U %s, T %g, p %g -> Mach %.6g" % (u_in, t_in, p_in, mach))
    for line in lines:
        print(line)
    foam_vtu.describe(grid, "VTK_" + {VTK_HEXAHEDRON: "HEXAHEDRON", VTK_WEDGE: "WEDGE",
                                      VTK_TETRA: "TETRA"}[cell_type], out)

    # ---- physics check on the grid read back
    ok = True
    if c["kind"] == "wedge":
        half = wedge
        axis = flow
        zs = [tip[2]] if c["mesher"] != "gmsh3d" else [tip[2] - 0.25 * c["span"], tip[2],
                                                       tip[2] + 0.25 * c["span"]]
        res = []
        for z in zs:
            res += [(z,) + r for r in shock_angle(back, np.array([tip[0], tip[1], z]), axis,
                                                   [np.array([0.0, 1.0, 0.0])], half, c["x1"], p_mid)]
        for z, b_meas, lo, hi, n in res:
            print("check       plane z = %+.4f: shock angle %.3f deg (line through the tip, %d stations; "
                  "local %.2f .. %.2f)" % (z, b_meas, n, lo, hi))
    elif c["kind"] == "cone":
        e1, e2 = np.array([0.0, 1.0, 0.0]), np.array([0.0, 0.0, 1.0])
        psis = (0.0, 45.0, 90.0)
        normals = [math.cos(math.radians(s)) * e1 + math.sin(math.radians(s)) * e2 for s in psis]
        # probed about the inflow direction (the fitted axis is within 0.01 deg of
        # it): the meridians 0 and 90 deg lie exactly in the symmetry planes, and
        # an axis off by 1e-9 would put them outside the domain
        res = [(s,) + r for s, r in zip(psis, shock_angle(back, tip, flow, normals, half, c["x1"], p_mid))]
        for s, b_meas, lo, hi, n in res:
            print("check       meridian %3g deg: shock angle %.3f deg (line through the tip, %d stations; "
                  "local %.2f .. %.2f)" % (s, b_meas, n, lo, hi))
    if c["kind"] in ("wedge", "cone"):
        b_mean = float(np.mean([r[1] for r in res]))
        tol = SHOCK_ANGLE_TOL[c["order"]]
        ok = all(abs(r[1] - want) <= tol for r in res)
        print("check       shock angle %.3f deg (mean) vs theory %.3f deg: %+.3f deg (tolerance %g on each) %s"
              % (b_mean, want, b_mean - want, tol, "ok" if ok else "FAILED"))
    else:
        # stagnation line y = 0 (z = 0 for the sphere; just inside the domain)
        o = np.array([centre[0], 1e-6 * rad, centre[2] + (1e-6 * rad if c["kind"] == "sphere" else 0.0)])
        x_s = last_crossing(back, o, np.array([-1.0, 0.0, 0.0]), rad * 1.0001, 10 * rad,
                            0.5 * p_in * (1.0 + p21))
        if x_s is None:
            sys.exit("bow shock not found on the stagnation line")
        standoff = x_s - rad
        p_stag, valid = probe_p(back, np.array([[centre[0] - rad * 1.0001, o[1], o[2]]]))
        ok_s = abs(standoff / standoff_b - 1.0) < 0.25
        ok_p = bool(valid[0]) and abs(p_stag[0] / p_in / pitot - 1.0) < 0.03
        ok = ok_s and ok_p
        print("check       standoff %.4f (%.4f R) vs Billig %.4f (%.4f R): %+.1f%% %s"
              % (standoff, standoff / rad, standoff_b, standoff_b / rad, 100 * (standoff / standoff_b - 1.0),
                 "ok" if ok_s else "FAILED"))
        print("check       stagnation point p/p1 %.4f vs pitot %.4f: %+.2f%% %s"
              % (p_stag[0] / p_in, pitot, 100 * (p_stag[0] / p_in / pitot - 1.0), "ok" if ok_p else "FAILED"))
    return 0 if ok else 1


def last_crossing(grid, origin, direction, s0, s1, level, n=2000):
    """Largest s in [s0, s1] where p(origin + s direction) crosses level (p of
    the vtkDataSet `grid`, linear between n samples), or None. Also used by
    Testing/Python/TestValidationCase.py."""
    import numpy as np
    from convert_cone20Ma2p5 import probe_p
    s = np.linspace(s0, s1, n)
    p, ok = probe_p(grid, origin + s[:, None] * direction)
    hit = np.where(ok[:-1] & ok[1:] & ((p[:-1] - level) * (p[1:] - level) <= 0.0) & (p[:-1] != p[1:]))[0]
    if len(hit) == 0:
        return None
    i = hit[-1]
    return s[i] + (level - p[i]) * (s[i + 1] - s[i]) / (p[i + 1] - p[i])


# ---------------------------------------------------------------------------- main
def main(argv):
    if len(argv) > 2 and argv[1] == "--convert":
        return convert(json.loads(argv[2]))
    ap = argparse.ArgumentParser(description="Make a small steady rhoCentralFoam validation solution (.vtu).",
                                 epilog="cases: " + ", ".join(CASES))
    ap.add_argument("case", nargs="?", choices=list(CASES), metavar="CASE_NAME")
    ap.add_argument("output", nargs="?", metavar="OUTPUT.vtu")
    ap.add_argument("--keep", metavar="DIR", help="build and keep the OpenFOAM case in DIR")
    ap.add_argument("--list", action="store_true", help="list the cases and their theory values")
    ap.add_argument("--refine", type=float, default=1.0, metavar="F",
                    help="refine the mesh uniformly: cell counts x F, Gmsh sizes / F (default 1)")
    ap.add_argument("--lts", action="store_true",
                    help="local time stepping (ddtSchemes localEuler, %(iterations)d iterations written every "
                    "%(write)d, maxCo %(maxco)g x the case's, rDeltaTSmoothingCoeff %(smoothing)g) instead of "
                    "Euler in time" % LTS)
    a = ap.parse_args(argv[1:])
    if not a.refine > 0:
        ap.error("--refine must be positive (got %g)" % a.refine)
    if a.list:
        for n, c in CASES.items():
            print("%-14s %s" % (n, theory(c)[2]))
        return 0
    if a.case is None or a.output is None:
        ap.error("CASE_NAME and OUTPUT.vtu are required")
    return make(a.case, os.path.abspath(a.output), a.keep, a.refine, a.lts)


if __name__ == "__main__":
    sys.exit(main(sys.argv))
