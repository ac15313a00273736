// SPDX-License-Identifier: BSD-3-Clause
#include "ARSurfaceFit.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>

namespace ar
{
namespace
{
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using VecX = Eigen::VectorXd;
using MatX = Eigen::MatrixXd;
constexpr double Pi = 3.14159265358979323846;

// Relative variance below which the points are taken as exactly collinear or
// coplanar (a standard deviation of 1e-7 of the largest one).
constexpr double DegenerateVariance = 1e-14;
// Relative threshold of the rank-revealing QR.
constexpr double RankThreshold = 1e-10;

Vec3 V3(const double* p)
{
  return Vec3(p[0], p[1], p[2]);
}
void Store(const Vec3& v, double* out)
{
  out[0] = v[0];
  out[1] = v[1];
  out[2] = v[2];
}

int PolynomialDegree(SurfaceTemplate t)
{
  switch (t)
  {
    case SurfaceTemplate::Plane:
      return 1;
    case SurfaceTemplate::Quadric:
      return 2;
    case SurfaceTemplate::Quartic:
      return 4;
    default:
      return 0;
  }
}

int NumberOfMonomials(int degree)
{
  return (degree + 1) * (degree + 2) / 2;
}

/// phi_k(x, y): by total degree, then by falling power of x.
void Monomials(int degree, double x, double y, double* phi)
{
  double xp[5] = { 1.0, x, x * x, x * x * x, x * x * x * x };
  double yp[5] = { 1.0, y, y * y, y * y * y, y * y * y * y };
  int k = 0;
  for (int d = 0; d <= degree; ++d)
  {
    for (int i = d; i >= 0; --i)
    {
      phi[k++] = xp[i] * yp[d - i];
    }
  }
}

/// z = f(x, y) and its first and second derivatives.
struct GraphValue
{
  double f = 0.0, fx = 0.0, fy = 0.0, fxx = 0.0, fxy = 0.0, fyy = 0.0;
};

GraphValue EvaluateGraph(int degree, const double* c, double x, double y)
{
  double xp[5] = { 1.0, x, x * x, x * x * x, x * x * x * x };
  double yp[5] = { 1.0, y, y * y, y * y * y, y * y * y * y };
  GraphValue g;
  int k = 0;
  for (int d = 0; d <= degree; ++d)
  {
    for (int i = d; i >= 0; --i, ++k)
    {
      const int j = d - i;
      const double ck = c[k];
      g.f += ck * xp[i] * yp[j];
      if (i >= 1)
      {
        g.fx += ck * i * xp[i - 1] * yp[j];
      }
      if (j >= 1)
      {
        g.fy += ck * j * xp[i] * yp[j - 1];
      }
      if (i >= 2)
      {
        g.fxx += ck * i * (i - 1) * xp[i - 2] * yp[j];
      }
      if (i >= 1 && j >= 1)
      {
        g.fxy += ck * i * j * xp[i - 1] * yp[j - 1];
      }
      if (j >= 2)
      {
        g.fyy += ck * j * (j - 1) * xp[i] * yp[j - 2];
      }
    }
  }
  return g;
}

/**
 * The foot of (X, Y, Z) on the graph z = f(x, y): Newton's method on
 * phi(x, y) = |(x, y, f(x, y)) - (X, Y, Z)|^2 / 2 from (u, v), with the
 * Gauss-Newton matrix where the Hessian is not positive definite, and
 * backtracking so that phi never grows.
 */
void FootOnGraph(int degree, const double* c, double X, double Y, double Z, double& u, double& v)
{
  for (int it = 0; it < 50; ++it)
  {
    const GraphValue g = EvaluateGraph(degree, c, u, v);
    const double e = g.f - Z;
    const double gx = (u - X) + e * g.fx;
    const double gy = (v - Y) + e * g.fy;
    double hxx = 1.0 + g.fx * g.fx + e * g.fxx;
    double hxy = g.fx * g.fy + e * g.fxy;
    double hyy = 1.0 + g.fy * g.fy + e * g.fyy;
    double det = hxx * hyy - hxy * hxy;
    if (!(hxx > 0.0 && det > 1e-12 * (hxx * hyy + 1e-300)))
    {
      hxx = 1.0 + g.fx * g.fx;
      hxy = g.fx * g.fy;
      hyy = 1.0 + g.fy * g.fy;
      det = hxx * hyy - hxy * hxy;
    }
    const double du = -(hyy * gx - hxy * gy) / det;
    const double dv = -(hxx * gy - hxy * gx) / det;
    const double phi0 = (u - X) * (u - X) + (v - Y) * (v - Y) + e * e;
    double step = 1.0;
    double un = u + du, vn = v + dv;
    for (int back = 0; back < 40; ++back)
    {
      un = u + step * du;
      vn = v + step * dv;
      const double en = EvaluateGraph(degree, c, un, vn).f - Z;
      const double phi = (un - X) * (un - X) + (vn - Y) * (vn - Y) + en * en;
      if (phi <= phi0)
      {
        break;
      }
      step *= 0.5;
    }
    const double moved = std::abs(un - u) + std::abs(vn - v);
    u = un;
    v = vn;
    if (!(moved > 1e-15 * (1.0 + std::abs(u) + std::abs(v))))
    {
      break;
    }
  }
}

/// A right-handed orthonormal frame.
struct Frame
{
  Vec3 O = Vec3::Zero(), X = Vec3::UnitX(), Y = Vec3::UnitY(), Z = Vec3::UnitZ();
  Vec3 ToLocal(const Vec3& p) const
  {
    const Vec3 q = p - this->O;
    return Vec3(q.dot(this->X), q.dot(this->Y), q.dot(this->Z));
  }
  Vec3 ToWorld(const Vec3& l) const { return this->O + l[0] * this->X + l[1] * this->Y + l[2] * this->Z; }
};

/// z along `axis` (unit); x along the coordinate axis least aligned with it.
Frame FrameFromAxis(const Vec3& origin, const Vec3& axis)
{
  Frame f;
  f.O = origin;
  f.Z = axis;
  int k = 0;
  for (int i = 1; i < 3; ++i)
  {
    if (std::abs(axis[i]) < std::abs(axis[k]))
    {
      k = i;
    }
  }
  const Vec3 e = Vec3::Unit(k);
  f.X = (e - e.dot(axis) * axis).normalized();
  f.Y = f.Z.cross(f.X);
  return f;
}

/// Weighted principal directions (weights w^2), ascending variances.
struct Principal
{
  Vec3 Centroid = Vec3::Zero();
  Vec3 Variances = Vec3::Zero();
  Mat3 Directions = Mat3::Identity(); // columns, ascending variance
};

/// Deterministic sign: the largest component positive.
void PositiveLargest(Vec3& d)
{
  Eigen::Index i;
  d.cwiseAbs().maxCoeff(&i);
  if (d[i] < 0.0)
  {
    d = -d;
  }
}

/// The weighted principal directions; with `dropAxis` (0, 1, 2) those of
/// the points projected along that coordinate axis (its own variance 0).
Principal WeightedPCA(const std::vector<Vec3>& pts, const VecX& w2, int dropAxis = -1)
{
  Principal pc;
  const double W = w2.sum();
  for (std::size_t j = 0; j < pts.size(); ++j)
  {
    pc.Centroid += w2[j] * pts[j];
  }
  pc.Centroid /= W;
  Mat3 C = Mat3::Zero();
  for (std::size_t j = 0; j < pts.size(); ++j)
  {
    Vec3 q = pts[j] - pc.Centroid;
    if (dropAxis >= 0)
    {
      q[dropAxis] = 0.0;
    }
    C.noalias() += w2[j] * q * q.transpose();
  }
  C /= W;
  Eigen::SelfAdjointEigenSolver<Mat3> es(C);
  pc.Variances = es.eigenvalues().cwiseMax(0.0);
  pc.Directions = es.eigenvectors();
  for (int k = 0; k < 3; ++k)
  {
    Vec3 d = pc.Directions.col(k);
    PositiveLargest(d);
    pc.Directions.col(k) = d;
  }
  return pc;
}

/// Frame of the principal directions: z smallest, x largest spread.
Frame PrincipalFrame(const Principal& pc)
{
  Frame f;
  f.O = pc.Centroid;
  f.Z = pc.Directions.col(0);
  f.X = pc.Directions.col(2);
  f.Y = f.Z.cross(f.X);
  return f;
}

/**
 * Levenberg-Marquardt on sum r_i(p)^2. `eval(p, r, J)` fills the residuals
 * and their Jacobian with respect to the step variables (returns false where
 * p is not admissible); `step(p, delta)` applies a step. Each step solves
 * min |[R; sqrt(lambda) D] delta + [Q^T r; 0]| with R from the Householder QR
 * of J and D the column norms of J (Marquardt's scaling). Returns the
 * number of accepted steps.
 */
int LevenbergMarquardt(VecX& p, int nstep, int maxIterations,
  const std::function<bool(const VecX&, VecX&, MatX&)>& eval,
  const std::function<VecX(const VecX&, const VecX&)>& step)
{
  VecX r;
  MatX J;
  if (!eval(p, r, J))
  {
    return 0;
  }
  double cost = r.squaredNorm();
  // Residuals are distances in coordinates scaled to O(1) with RMS weight 1:
  // below this floor only round-off is left.
  const double floor = 1e-28 * static_cast<double>(r.size());
  double lambda = 1e-3;
  int accepted = 0;
  VecX rNew;
  MatX JNew;
  for (int it = 0; it < maxIterations && cost > floor; ++it)
  {
    VecX D = J.colwise().norm().transpose();
    const double dmax = std::max(D.maxCoeff(), 1e-300);
    D = D.cwiseMax(1e-12 * dmax);
    Eigen::HouseholderQR<MatX> qr(J);
    const MatX R = qr.matrixQR().topRows(nstep).triangularView<Eigen::Upper>();
    const VecX qtr = (qr.householderQ().adjoint() * r).head(nstep);
    if (qtr.norm() <= 1e-12 * std::sqrt(cost))
    {
      break; // stationary: r is orthogonal to the range of J
    }
    bool improved = false;
    bool converged = false;
    double grow = 10.0;
    for (int attempt = 0; attempt < 30 && lambda < 1e20; ++attempt)
    {
      MatX M(2 * nstep, nstep);
      M.topRows(nstep) = R;
      M.bottomRows(nstep) = (std::sqrt(lambda) * D).asDiagonal();
      VecX rhs = VecX::Zero(2 * nstep);
      rhs.head(nstep) = -qtr;
      const VecX delta = M.householderQr().solve(rhs);
      double costNew = std::numeric_limits<double>::infinity();
      VecX pNew;
      if (delta.allFinite())
      {
        pNew = step(p, delta);
        if (eval(pNew, rNew, JNew))
        {
          costNew = rNew.squaredNorm();
        }
      }
      if (costNew < cost)
      {
        converged = (cost - costNew) <= 1e-12 * cost;
        p = pNew;
        r.swap(rNew);
        J.swap(JNew);
        cost = costNew;
        lambda = std::max(lambda / 3.0, 1e-12);
        improved = true;
        ++accepted;
        break;
      }
      lambda *= grow;
      grow *= 4.0;
    }
    if (!improved || converged)
    {
      break;
    }
  }
  return accepted;
}

//------------------------------------------------------------------------------
// Graph surfaces z = f(x, y) in a frame (plane, quadric, quartic).

/// The points in frame coordinates scaled by S, and the weights.
struct GraphData
{
  int Degree = 1;
  int M = 3;
  double S = 1.0;
  std::vector<Vec3> P; // scaled local coordinates
  VecX W;              // normalized weights
};

/// Orthogonal residuals w_j d_j of scaled coefficients c; feet warm-started.
bool GraphResiduals(const GraphData& g, const VecX& c, std::vector<double>& fu,
  std::vector<double>& fv, VecX& r, MatX* J)
{
  const std::size_t n = g.P.size();
  r.resize(n);
  if (J)
  {
    J->resize(n, g.M);
  }
  double phi[15];
  for (std::size_t j = 0; j < n; ++j)
  {
    const Vec3& P = g.P[j];
    FootOnGraph(g.Degree, c.data(), P[0], P[1], P[2], fu[j], fv[j]);
    const GraphValue gv = EvaluateGraph(g.Degree, c.data(), fu[j], fv[j]);
    const double gn = std::sqrt(1.0 + gv.fx * gv.fx + gv.fy * gv.fy);
    const double d = (-(P[0] - fu[j]) * gv.fx - (P[1] - fv[j]) * gv.fy + (P[2] - gv.f)) / gn;
    r[j] = g.W[j] * d;
    if (J)
    {
      Monomials(g.Degree, fu[j], fv[j], phi);
      for (int k = 0; k < g.M; ++k)
      {
        (*J)(j, k) = -g.W[j] * phi[k] / gn;
      }
    }
  }
  return r.allFinite() && (!J || J->allFinite());
}

bool FitGraph(const std::vector<Vec3>& pts, const VecX& w, const Principal& pc,
  const SurfaceFitOptions& options, SurfaceFitResult& result, std::string& error)
{
  const SurfaceTemplate t = options.Template;
  Frame frame;
  const Vec3 graphAxis = V3(options.GraphAxis);
  if (options.AutomaticAxis && options.ExtrusionAxis < 0 && graphAxis.norm() > 0.0)
  {
    frame = FrameFromAxis(pc.Centroid, graphAxis.normalized()); // through the points' weighted centroid
  }
  else if (options.AutomaticAxis)
  {
    frame = PrincipalFrame(pc);
  }
  else
  {
    frame = FrameFromAxis(V3(options.AxisOrigin), V3(options.AxisDirection).normalized());
  }
  GraphData g;
  g.Degree = PolynomialDegree(t);
  g.M = NumberOfMonomials(g.Degree);
  g.W = w;
  const std::size_t n = pts.size();
  g.P.resize(n);
  double s2 = 0.0;
  for (std::size_t j = 0; j < n; ++j)
  {
    g.P[j] = frame.ToLocal(pts[j]);
    s2 += w[j] * w[j] * (g.P[j][0] * g.P[j][0] + g.P[j][1] * g.P[j][1]);
  }
  g.S = std::sqrt(s2 / w.squaredNorm());
  if (!(g.S > 0.0))
  {
    error = "The points all project onto one point of the plane across the axis: a surface "
            "z = f(x, y) is not determined (is the axis along the points' spread?).";
    return false;
  }
  for (Vec3& P : g.P)
  {
    P /= g.S;
  }

  // The coefficients fitted: all of them, or on a surface extruded along the
  // frame's y (ExtrusionAxis with the automatic frame, whose y is then that
  // axis) only those of the monomials without y, so that z = f(x) is a
  // cylinder over the axis: the two levels of a one-cell-deep mesh's points
  // would otherwise let f bend along the depth.
  const bool extruded = options.ExtrusionAxis >= 0 && options.AutomaticAxis;
  std::vector<int> active;
  for (int d = 0, k = 0; d <= g.Degree; ++d)
  {
    for (int i = d; i >= 0; --i, ++k)
    {
      if (!extruded || i == d)
      {
        active.push_back(k);
      }
    }
  }
  const int m = static_cast<int>(active.size());
  auto scatter = [&](const VecX& reduced) {
    VecX full = VecX::Zero(g.M);
    for (int q = 0; q < m; ++q)
    {
      full[active[q]] = reduced[q];
    }
    return full;
  };

  // ---- Eq. 4: vertical offsets, weighted, by rank-revealing QR.
  MatX A(n, m);
  VecX b(n);
  double phi[15];
  for (std::size_t j = 0; j < n; ++j)
  {
    Monomials(g.Degree, g.P[j][0], g.P[j][1], phi);
    for (int q = 0; q < m; ++q)
    {
      A(j, q) = w[j] * phi[active[q]];
    }
    b[j] = w[j] * g.P[j][2];
  }
  Eigen::ColPivHouseholderQR<MatX> qr(A);
  qr.setThreshold(RankThreshold);
  if (qr.rank() < m)
  {
    std::ostringstream msg;
    msg << "Singular system: the " << n << " points do not determine the " << m
        << " coefficients of the " << SurfaceTemplateName(t)
        << (extruded ? " z = f(x) extruded along the axis" : " z = f(x, y)") << " (rank "
        << qr.rank() << "): their projections across the axis lie on "
        << (extruded ? "too few distinct positions." : "a line or a low-degree curve.");
    error = msg.str();
    return false;
  }
  VecX cr = qr.solve(b);
  VecX c = scatter(cr);

  Store(frame.O, result.FrameOrigin);
  Store(frame.X, result.FrameX);
  Store(frame.Y, result.FrameY);
  Store(frame.Z, result.FrameZ);

  if (t == SurfaceTemplate::Plane)
  {
    Vec3 normal, origin;
    if (options.GeometricRefinement)
    {
      // The plane minimizing sum (w d)^2 goes through the weighted centroid
      // with the direction of least weighted spread as its normal.
      normal = pc.Directions.col(0);
      origin = pc.Centroid;
      result.Refined = true;
    }
    else
    {
      // z = c0 S + c1 x + c2 y in the frame.
      const Vec3 nl = Vec3(-c[1], -c[2], 1.0).normalized();
      normal = nl[0] * frame.X + nl[1] * frame.Y + nl[2] * frame.Z;
      const Vec3 onPlane = frame.O + c[0] * g.S * frame.Z;
      origin = pc.Centroid - (pc.Centroid - onPlane).dot(normal) * normal;
    }
    if (normal.dot(frame.Z) < 0.0)
    {
      normal = -normal;
    }
    Store(normal, result.Normal);
    Store(origin, result.Origin);
    result.Coefficients = { normal[0], normal[1], normal[2], -normal.dot(origin) };
    return true;
  }

  std::vector<double> fu(n), fv(n);
  for (std::size_t j = 0; j < n; ++j)
  {
    fu[j] = g.P[j][0];
    fv[j] = g.P[j][1];
  }
  if (options.GeometricRefinement)
  {
    MatX Jfull;
    result.Iterations = LevenbergMarquardt(
      cr, m, options.MaximumIterations,
      [&](const VecX& p, VecX& r, MatX& J) {
        if (!GraphResiduals(g, scatter(p), fu, fv, r, &Jfull))
        {
          return false;
        }
        J.resize(static_cast<Eigen::Index>(n), m);
        for (int q = 0; q < m; ++q)
        {
          J.col(q) = Jfull.col(active[q]);
        }
        return true;
      },
      [](const VecX& p, const VecX& delta) -> VecX { return p + delta; });
    c = scatter(cr);
    result.Refined = true;
  }
  // Unscale: z/S = sum c~_ik (x/S)^i (y/S)^k  ->  c_ik = c~_ik S^(1-i-k).
  result.Coefficients.resize(g.M);
  int k = 0;
  for (int d = 0; d <= g.Degree; ++d)
  {
    for (int i = d; i >= 0; --i, ++k)
    {
      result.Coefficients[k] = c[k] * std::pow(g.S, 1 - d);
    }
  }
  return true;
}

//------------------------------------------------------------------------------
// Cone.

struct Cone
{
  Vec3 Apex = Vec3::Zero();
  Vec3 Axis = Vec3::UnitZ();
  double Theta = 0.0; // half-angle, radians
};

bool Admissible(const Cone& k)
{
  // Half-angles below 0.01 degree are cylinders; apexes a million point-cloud
  // radii away are planes or cylinders too.
  return k.Apex.allFinite() && k.Axis.allFinite() && std::isfinite(k.Theta) &&
    k.Theta > 1e-2 * Pi / 180.0 && k.Theta < 0.5 * Pi - 1e-9 && k.Apex.norm() < 1e6;
}

/// Signed distance from the cone's nappe (positive outside) and its
/// derivatives with respect to apex (3), axis along t1, t2 (2), angle (1).
double ConeDistance(const Cone& k, const Vec3& p, const Vec3& t1, const Vec3& t2, double* grad)
{
  const Vec3 v = p - k.Apex;
  const double h = v.dot(k.Axis);
  const Vec3 radial = v - h * k.Axis;
  const double rho = radial.norm();
  const double c = std::cos(k.Theta), s = std::sin(k.Theta);
  if (h * c + rho * s >= 0.0)
  {
    const Vec3 e = rho > 1e-300 ? Vec3(radial / rho) : t1;
    if (grad)
    {
      const Vec3 ga = -c * e + s * k.Axis;
      const double f = rho > 1e-300 ? -(h * c / rho + s) : -s;
      const Vec3 gd = f * v;
      grad[0] = ga[0];
      grad[1] = ga[1];
      grad[2] = ga[2];
      grad[3] = gd.dot(t1);
      grad[4] = gd.dot(t2);
      grad[5] = -rho * s - h * c;
    }
    return rho * c - h * s;
  }
  // Behind the apex: the apex is the closest point.
  const double dist = v.norm();
  if (grad)
  {
    const Vec3 ga = dist > 1e-300 ? Vec3(-v / dist) : Vec3::Zero();
    grad[0] = ga[0];
    grad[1] = ga[1];
    grad[2] = ga[2];
    grad[3] = grad[4] = grad[5] = 0.0;
  }
  return dist;
}

double ConeCost(const Cone& k, const std::vector<Vec3>& P, const VecX& w)
{
  double cost = 0.0;
  for (std::size_t j = 0; j < P.size(); ++j)
  {
    const double d = w[j] * ConeDistance(k, P[j], Vec3::Zero(), Vec3::Zero(), nullptr);
    cost += d * d;
  }
  return cost;
}

/// Orients the axis towards the side of the apex where most weight lies.
void OrientNappe(Cone& k, const std::vector<Vec3>& P, const VecX& w)
{
  double side = 0.0;
  for (std::size_t j = 0; j < P.size(); ++j)
  {
    side += w[j] * w[j] * (P[j] - k.Apex).dot(k.Axis);
  }
  if (side < 0.0)
  {
    k.Axis = -k.Axis;
  }
}

/// With the axis direction fixed, (x-x0)^2 + (y-y0)^2 = k^2 (z-z0)^2 is
/// linear in (2 x0, 2 y0, k^2, -2 k^2 z0, const): apex and angle.
bool ConeWithAxisDirection(
  const std::vector<Vec3>& P, const VecX& w, const Vec3& axis, Cone& cone)
{
  const Frame f = FrameFromAxis(Vec3::Zero(), axis);
  const std::size_t n = P.size();
  MatX A(n, 5);
  VecX b(n);
  for (std::size_t j = 0; j < n; ++j)
  {
    const Vec3 l = f.ToLocal(P[j]);
    A.row(j) << w[j] * l[0], w[j] * l[1], w[j] * l[2] * l[2], w[j] * l[2], w[j];
    b[j] = w[j] * (l[0] * l[0] + l[1] * l[1]);
  }
  Eigen::ColPivHouseholderQR<MatX> qr(A);
  qr.setThreshold(RankThreshold);
  if (qr.rank() < 5)
  {
    return false;
  }
  const VecX q = qr.solve(b);
  if (!(q[2] > 0.0))
  {
    return false;
  }
  const double x0 = 0.5 * q[0], y0 = 0.5 * q[1], z0 = -q[3] / (2.0 * q[2]);
  cone.Apex = f.ToWorld(Vec3(x0, y0, z0));
  cone.Axis = axis;
  cone.Theta = std::atan(std::sqrt(q[2]));
  OrientNappe(cone, P, w);
  return Admissible(cone);
}

/// Eq. 4 for a cone about a given axis line: z = z_apex + cot(theta) rho.
bool ConeAlongAxisLine(const std::vector<Vec3>& P, const VecX& w, const Vec3& origin,
  const Vec3& axis, Cone& cone)
{
  const Frame f = FrameFromAxis(origin, axis);
  const std::size_t n = P.size();
  MatX A(n, 2);
  VecX b(n);
  for (std::size_t j = 0; j < n; ++j)
  {
    const Vec3 l = f.ToLocal(P[j]);
    A(j, 0) = w[j];
    A(j, 1) = w[j] * std::sqrt(l[0] * l[0] + l[1] * l[1]);
    b[j] = w[j] * l[2];
  }
  Eigen::ColPivHouseholderQR<MatX> qr(A);
  qr.setThreshold(RankThreshold);
  if (qr.rank() < 2)
  {
    return false;
  }
  const VecX q = qr.solve(b);
  cone.Apex = origin + q[0] * axis;
  cone.Axis = q[1] >= 0.0 ? axis : Vec3(-axis);
  cone.Theta = std::atan(1.0 / std::abs(q[1]));
  return Admissible(cone);
}

int RefineCone(Cone& cone, const std::vector<Vec3>& P, const VecX& w, int maxIterations)
{
  VecX p(7);
  p << cone.Apex, cone.Axis, cone.Theta;
  const std::size_t n = P.size();
  auto unpack = [](const VecX& q) {
    Cone k;
    k.Apex = q.head<3>();
    k.Axis = q.segment<3>(3);
    k.Theta = q[6];
    return k;
  };
  const int accepted = LevenbergMarquardt(
    p, 6, maxIterations,
    [&](const VecX& q, VecX& r, MatX& J) {
      const Cone k = unpack(q);
      if (!Admissible(k))
      {
        return false;
      }
      const Frame f = FrameFromAxis(Vec3::Zero(), k.Axis);
      r.resize(n);
      J.resize(n, 6);
      double grad[6];
      for (std::size_t j = 0; j < n; ++j)
      {
        r[j] = w[j] * ConeDistance(k, P[j], f.X, f.Y, grad);
        for (int c = 0; c < 6; ++c)
        {
          J(j, c) = w[j] * grad[c];
        }
      }
      return r.allFinite() && J.allFinite();
    },
    [](const VecX& q, const VecX& delta) -> VecX {
      const Frame f = FrameFromAxis(Vec3::Zero(), q.segment<3>(3));
      VecX out = q;
      out.head<3>() += delta.head<3>();
      out.segment<3>(3) = (f.Z + delta[3] * f.X + delta[4] * f.Y).normalized();
      out[6] += delta[5];
      return out;
    });
  cone = unpack(p);
  return accepted;
}

/// Candidate axis directions: the eigenvectors of the quadratic part of the
/// general quadric through the points (algebraic fit, smallest singular
/// vector of the weighted design matrix via QR then SVD of R).
std::vector<Vec3> QuadricAxes(const std::vector<Vec3>& P, const VecX& w)
{
  const std::size_t n = P.size();
  MatX A(n, 10);
  for (std::size_t j = 0; j < n; ++j)
  {
    const Vec3& x = P[j];
    A.row(j) << x[0] * x[0], x[1] * x[1], x[2] * x[2], x[0] * x[1], x[0] * x[2], x[1] * x[2],
      x[0], x[1], x[2], 1.0;
    A.row(j) *= w[j];
  }
  Eigen::HouseholderQR<MatX> qr(A);
  const Eigen::Matrix<double, 10, 10> R =
    qr.matrixQR().topRows(10).triangularView<Eigen::Upper>();
  Eigen::JacobiSVD<Eigen::Matrix<double, 10, 10>> svd(R, Eigen::ComputeFullV);
  const Eigen::Matrix<double, 10, 1> q = svd.matrixV().col(9);
  Mat3 Q;
  Q << q[0], 0.5 * q[3], 0.5 * q[4], 0.5 * q[3], q[1], 0.5 * q[5], 0.5 * q[4], 0.5 * q[5], q[2];
  Eigen::SelfAdjointEigenSolver<Mat3> es(Q);
  // The eigenvalue of a cone's axis has the sign opposite to the other two:
  // try that one first (the order only matters for ties).
  const Vec3 ev = es.eigenvalues();
  std::vector<int> order = { 0, 1, 2 };
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    auto odd = [&](int i) {
      const int s0 = ev[i] > 0.0, s1 = ev[(i + 1) % 3] > 0.0, s2 = ev[(i + 2) % 3] > 0.0;
      return s0 != s1 && s1 == s2;
    };
    return odd(a) && !odd(b);
  });
  std::vector<Vec3> axes;
  for (int i : order)
  {
    axes.push_back(es.eigenvectors().col(i));
  }
  return axes;
}

bool FitCone(const std::vector<Vec3>& pts, const VecX& w, const Principal& pc,
  const SurfaceFitOptions& options, SurfaceFitResult& result, std::string& error)
{
  // Centred and scaled coordinates.
  const double L = std::sqrt(pc.Variances.sum());
  std::vector<Vec3> P(pts.size());
  for (std::size_t j = 0; j < pts.size(); ++j)
  {
    P[j] = (pts[j] - pc.Centroid) / L;
  }
  // Starts of the orthogonal-distance fit; without refinement and with the
  // user's axis, Eq. 4 about that axis is the answer.
  std::vector<Cone> starts;
  Cone k;
  const bool userAxisOnly = !options.AutomaticAxis && !options.GeometricRefinement;
  if (options.AutomaticAxis)
  {
    if (pts.size() < 10)
    {
      error = "The automatic cone axis needs at least 10 points (a general quadric through "
              "them); there are " + std::to_string(pts.size()) +
        ". Give the axis (UseAutomaticAxis off).";
      return false;
    }
    for (const Vec3& axis : QuadricAxes(P, w))
    {
      if (ConeWithAxisDirection(P, w, axis, k))
      {
        starts.push_back(k);
        Cone e;
        if (ConeAlongAxisLine(P, w, k.Apex, k.Axis, e))
        {
          starts.push_back(e);
        }
      }
    }
  }
  else
  {
    const Vec3 axis = V3(options.AxisDirection).normalized();
    const Vec3 origin = (V3(options.AxisOrigin) - pc.Centroid) / L;
    if (ConeAlongAxisLine(P, w, origin, axis, k))
    {
      starts.push_back(k);
    }
    if (!userAxisOnly && ConeWithAxisDirection(P, w, axis, k))
    {
      starts.push_back(k);
    }
  }
  double best = std::numeric_limits<double>::infinity();
  Cone winner;
  int iterations = 0;
  for (Cone c : starts)
  {
    const int it = userAxisOnly ? 0 : RefineCone(c, P, w, options.MaximumIterations);
    const double cost = ConeCost(c, P, w);
    if (Admissible(c) && cost < best)
    {
      best = cost;
      winner = c;
      iterations = it;
    }
  }
  // The automatic axis is the axis of the best orthogonal fit; without
  // refinement, Eq. 4 about that axis line is the answer.
  if (options.AutomaticAxis && !options.GeometricRefinement && std::isfinite(best))
  {
    Cone e;
    if (ConeAlongAxisLine(P, w, winner.Apex, winner.Axis, e))
    {
      winner = e;
    }
    else
    {
      best = std::numeric_limits<double>::infinity();
    }
    iterations = 0;
  }
  if (!std::isfinite(best))
  {
    error = options.AutomaticAxis
      ? "No cone fits the points: the general quadric through them has no axis along which a "
        "cone z = z_apex + cot(theta) rho fits. Give an approximate axis (UseAutomaticAxis off)."
      : "No cone fits the points about the given axis (the fitted half-angle is not between 0 "
        "and 90 degrees, or the distance from the axis does not vary). Check AxisDirection.";
    return false;
  }
  if (winner.Theta > 0.5 * Pi - 1e-3)
  {
    error = "The fitted cone's half-angle is " + std::to_string(winner.Theta * 180.0 / Pi) +
      " degrees: the points lie on a plane, not a cone. Use the Plane template.";
    return false;
  }
  const Vec3 apex = pc.Centroid + L * winner.Apex;
  Store(apex, result.Apex);
  Store(winner.Axis, result.AxisDirection);
  result.HalfAngleDegrees = winner.Theta * 180.0 / Pi;
  result.Coefficients = { apex[0], apex[1], apex[2], winner.Axis[0], winner.Axis[1],
    winner.Axis[2], result.HalfAngleDegrees };
  const Frame f = FrameFromAxis(apex, winner.Axis);
  Store(f.O, result.FrameOrigin);
  Store(f.X, result.FrameX);
  Store(f.Y, result.FrameY);
  Store(f.Z, result.FrameZ);
  result.Iterations = iterations;
  result.Refined = options.GeometricRefinement;
  return true;
}

bool Finite3(const double* v)
{
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}
}

//------------------------------------------------------------------------------
const char* SurfaceTemplateName(SurfaceTemplate t)
{
  switch (t)
  {
    case SurfaceTemplate::Plane:
      return "Plane";
    case SurfaceTemplate::Quadric:
      return "Quadric";
    case SurfaceTemplate::Cone:
      return "Cone";
    case SurfaceTemplate::Quartic:
      return "Quartic";
  }
  return "Unknown";
}

std::size_t SurfaceTemplateMinimumPoints(SurfaceTemplate t)
{
  switch (t)
  {
    case SurfaceTemplate::Plane:
      return 3;
    case SurfaceTemplate::Quadric:
      return 6;
    case SurfaceTemplate::Cone:
      return 6;
    case SurfaceTemplate::Quartic:
      return 15;
  }
  return 0;
}

//------------------------------------------------------------------------------
bool FitSurface(const double* points, const double* weights, std::size_t n,
  const SurfaceFitOptions& options, SurfaceFitResult& result, std::string& error)
{
  result = SurfaceFitResult();
  result.Template = options.Template;
  result.NumberOfPoints = n;
  const SurfaceTemplate t = options.Template;
  const char* name = SurfaceTemplateName(t);
  if (std::string(name) == "Unknown")
  {
    error = "Unknown template (use Plane 0, Quadric 1, Cone 2 or Quartic 3).";
    return false;
  }
  const std::size_t need = SurfaceTemplateMinimumPoints(t);
  if (n < need || !points)
  {
    error = std::string("Too few points: the ") + name + " needs at least " +
      std::to_string(need) + ", there are " + std::to_string(n) + ".";
    return false;
  }
  for (std::size_t j = 0; j < n; ++j)
  {
    if (!Finite3(points + 3 * j))
    {
      error = "Point " + std::to_string(j) + " has a NaN or infinite coordinate.";
      return false;
    }
    if (weights && !(std::isfinite(weights[j]) && weights[j] > 0.0))
    {
      std::ostringstream msg;
      msg << "The weight of point " << j << " is " << weights[j]
          << ": weights (1 / local size) must be positive and finite.";
      error = msg.str();
      return false;
    }
  }
  if (options.ExtrusionAxis < -1 || options.ExtrusionAxis > 2)
  {
    error = "ExtrusionAxis is " + std::to_string(options.ExtrusionAxis) +
      "; it must be -1 (none) or a coordinate axis 0, 1 or 2.";
    return false;
  }
  if (!options.AutomaticAxis)
  {
    if (!Finite3(options.AxisDirection) || !Finite3(options.AxisOrigin))
    {
      error = "The axis origin or direction has a NaN or infinite component.";
      return false;
    }
    if (!(V3(options.AxisDirection).norm() > 0.0))
    {
      error = "Degenerate axis: AxisDirection is the zero vector.";
      return false;
    }
  }

  std::vector<Vec3> pts(n);
  VecX w(n);
  for (std::size_t j = 0; j < n; ++j)
  {
    pts[j] = V3(points + 3 * j);
    w[j] = weights ? weights[j] : 1.0;
  }
  w /= std::sqrt(w.squaredNorm() / static_cast<double>(n)); // RMS weight 1
  const VecX w2 = w.cwiseProduct(w);
  Principal pc = WeightedPCA(pts, w2);
  if (options.ExtrusionAxis >= 0)
  {
    // A surface extruded along a coordinate axis (a one-cell-deep mesh's
    // points): the frame's z (the plane's normal) lies across the axis, x
    // along the points' largest spread across it, y along the axis. The
    // smallest spread is often the depth itself (a curved piece of a 2-D
    // shock is thicker across than the mesh is deep), which would make the
    // front plane the fit.
    const int a = options.ExtrusionAxis;
    const Principal across = WeightedPCA(pts, w2, a);
    Vec3 axis = Vec3::Zero();
    axis[a] = 1.0;
    const Vec3 major = across.Directions.col(2);
    Vec3 minor = axis.cross(major).normalized(); // exact, however thin the spread across
    PositiveLargest(minor);
    const double along = pc.Variances.sum() - across.Variances.sum();
    pc.Directions.col(0) = minor;
    pc.Directions.col(1) = axis;
    pc.Directions.col(2) = major;
    pc.Variances = Vec3(across.Variances[1], std::max(along, 0.0), across.Variances[2]);
  }
  const double total = pc.Variances.sum();
  if (!(total > 0.0))
  {
    error = "All " + std::to_string(n) + " points coincide.";
    return false;
  }
  const bool collinear = pc.Variances[1] <= DegenerateVariance * pc.Variances[2];
  const bool coplanar = pc.Variances[0] <= DegenerateVariance * pc.Variances[2];
  if (collinear && t != SurfaceTemplate::Cone)
  {
    error = std::string("The points are collinear: they do not determine a ") + name + ".";
    return false;
  }
  if (t == SurfaceTemplate::Cone && (collinear || coplanar))
  {
    error = collinear ? "The points are collinear: they do not determine a cone."
                      : "The points are coplanar: they do not determine a cone (use the Plane "
                        "template).";
    return false;
  }

  const bool ok = t == SurfaceTemplate::Cone ? FitCone(pts, w, pc, options, result, error)
                                             : FitGraph(pts, w, pc, options, result, error);
  if (!ok)
  {
    return false;
  }
  for (double c : result.Coefficients)
  {
    if (!std::isfinite(c))
    {
      error = "The fit produced non-finite coefficients (an ill-conditioned system).";
      return false;
    }
  }
  double sum = 0.0, wsum = 0.0;
  for (std::size_t j = 0; j < n; ++j)
  {
    const double d = SurfaceDistance(result, points + 3 * j);
    sum += d * d;
    wsum += w2[j] * d * d;
  }
  result.RMSResidual = std::sqrt(sum / static_cast<double>(n));
  result.WeightedRMSResidual = std::sqrt(wsum / w2.sum());
  return true;
}

//------------------------------------------------------------------------------
namespace
{
Frame ResultFrame(const SurfaceFitResult& fit)
{
  Frame f;
  f.O = V3(fit.FrameOrigin);
  f.X = V3(fit.FrameX);
  f.Y = V3(fit.FrameY);
  f.Z = V3(fit.FrameZ);
  return f;
}

Cone ResultCone(const SurfaceFitResult& fit)
{
  Cone k;
  k.Apex = V3(fit.Apex);
  k.Axis = V3(fit.AxisDirection);
  k.Theta = fit.HalfAngleDegrees * Pi / 180.0;
  return k;
}
}

double SurfaceDistance(const SurfaceFitResult& fit, const double p[3])
{
  switch (fit.Template)
  {
    case SurfaceTemplate::Plane:
      return (V3(p) - V3(fit.Origin)).dot(V3(fit.Normal));
    case SurfaceTemplate::Cone:
      return ConeDistance(ResultCone(fit), V3(p), Vec3::Zero(), Vec3::Zero(), nullptr);
    default:
    {
      const Frame f = ResultFrame(fit);
      const Vec3 l = f.ToLocal(V3(p));
      const int degree = PolynomialDegree(fit.Template);
      double u = l[0], v = l[1];
      FootOnGraph(degree, fit.Coefficients.data(), l[0], l[1], l[2], u, v);
      const GraphValue g = EvaluateGraph(degree, fit.Coefficients.data(), u, v);
      return (-(l[0] - u) * g.fx - (l[1] - v) * g.fy + (l[2] - g.f)) /
        std::sqrt(1.0 + g.fx * g.fx + g.fy * g.fy);
    }
  }
}

void ProjectOntoSurface(const SurfaceFitResult& fit, const double p[3], double foot[3])
{
  Vec3 q;
  switch (fit.Template)
  {
    case SurfaceTemplate::Plane:
    {
      const Vec3 nrm = V3(fit.Normal);
      q = V3(p) - (V3(p) - V3(fit.Origin)).dot(nrm) * nrm;
      break;
    }
    case SurfaceTemplate::Cone:
    {
      const Cone k = ResultCone(fit);
      const Vec3 v = V3(p) - k.Apex;
      const double h = v.dot(k.Axis);
      const Vec3 radial = v - h * k.Axis;
      const double rho = radial.norm();
      const Vec3 e = rho > 1e-300 ? Vec3(radial / rho) : FrameFromAxis(Vec3::Zero(), k.Axis).X;
      const Vec3 generator = std::cos(k.Theta) * k.Axis + std::sin(k.Theta) * e;
      const double s = std::max(0.0, v.dot(generator));
      q = k.Apex + s * generator;
      break;
    }
    default:
    {
      const Frame f = ResultFrame(fit);
      const Vec3 l = f.ToLocal(V3(p));
      const int degree = PolynomialDegree(fit.Template);
      double u = l[0], v = l[1];
      FootOnGraph(degree, fit.Coefficients.data(), l[0], l[1], l[2], u, v);
      q = f.ToWorld(Vec3(u, v, EvaluateGraph(degree, fit.Coefficients.data(), u, v).f));
    }
  }
  Store(q, foot);
}

//------------------------------------------------------------------------------
namespace
{
/// Triangles between two rows of points ordered by a parameter: A below, B
/// above; advances along the row whose next point comes first, which gives
/// the near-equilateral pattern of rows offset by half a spacing.
void Zip(const std::vector<double>& ta, const std::vector<std::int64_t>& ia,
  const std::vector<double>& tb, const std::vector<std::int64_t>& ib,
  std::vector<std::int64_t>& tris)
{
  std::size_t i = 0, j = 0;
  while (i + 1 < ta.size() || j + 1 < tb.size())
  {
    const bool advanceA =
      j + 1 >= tb.size() || (i + 1 < ta.size() && ta[i + 1] <= tb[j + 1]);
    if (advanceA)
    {
      tris.insert(tris.end(), { ia[i], ia[i + 1], ib[j] });
      ++i;
    }
    else
    {
      tris.insert(tris.end(), { ia[i], ib[j + 1], ib[j] });
      ++j;
    }
  }
}

bool TooMany(double triangles, std::size_t maxTriangles, std::string& error)
{
  if (triangles > static_cast<double>(maxTriangles))
  {
    std::ostringstream msg;
    msg << "The surface mesh would have about " << static_cast<double>(triangles)
        << " triangles (more than " << maxTriangles
        << "): the edge length is too small for the surface's extent.";
    error = msg.str();
    return true;
  }
  return false;
}

bool TessellateGraph(const SurfaceFitResult& fit, const double* points, std::size_t n, double h,
  double reach, SurfaceMesh& mesh, std::string& error, std::size_t maxTriangles)
{
  const bool plane = fit.Template == SurfaceTemplate::Plane;
  const Frame f = plane ? FrameFromAxis(V3(fit.Origin), V3(fit.Normal)) : ResultFrame(fit);
  const int degree = PolynomialDegree(fit.Template);
  std::vector<double> fx(n), fy(n);
  double lo[2] = { std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity() };
  double hi[2] = { -lo[0], -lo[1] };
  for (std::size_t j = 0; j < n; ++j)
  {
    double foot[3];
    ProjectOntoSurface(fit, points + 3 * j, foot);
    const Vec3 l = f.ToLocal(V3(foot));
    fx[j] = l[0];
    fy[j] = l[1];
    lo[0] = std::min(lo[0], l[0]);
    lo[1] = std::min(lo[1], l[1]);
    hi[0] = std::max(hi[0], l[0]);
    hi[1] = std::max(hi[1], l[1]);
  }
  const double pad = reach + h;
  const double dy = h * std::sqrt(3.0) / 2.0;
  // The grid is centred on the feet: a column and a row pass through the
  // middle of their box. A surface across a one-cell-deep mesh (the plane's
  // frame x then runs along the depth) thus has points at mid-depth, and the
  // domain's trim keeps the strip inside the slab; with the grid starting
  // anywhere, a slab thinner than the edge could fall between two columns
  // and be trimmed away.
  const double step[2] = { h, dy };
  for (int k = 0; k < 2; ++k)
  {
    const double mid = 0.5 * (lo[k] + hi[k]);
    lo[k] = mid - std::ceil((mid - lo[k] + pad) / step[k]) * step[k];
    hi[k] = mid + std::ceil((hi[k] - mid + pad) / step[k]) * step[k];
  }
  const double nxd = std::ceil((hi[0] - lo[0]) / h) + 1.0;
  const double nyd = std::ceil((hi[1] - lo[1]) / dy);
  if (TooMany(2.0 * nxd * nyd, maxTriangles, error))
  {
    return false;
  }
  const std::int64_t nx = static_cast<std::int64_t>(nxd);
  const std::int64_t ny = static_cast<std::int64_t>(nyd);

  // Bins of side `pad` marking where feet are: a triangle is kept when one of
  // its points lies in a bin next to a marked one (everything within `pad`
  // of a foot is kept; the caller trims precisely).
  const double bin = pad;
  const std::int64_t bx = static_cast<std::int64_t>(std::ceil((hi[0] - lo[0] + h) / bin)) + 1;
  const std::int64_t by = static_cast<std::int64_t>(std::ceil((hi[1] - lo[1] + h) / bin)) + 1;
  std::vector<std::uint8_t> near(static_cast<std::size_t>(bx * by), 0);
  auto binOf = [&](double x, double y, std::int64_t& i, std::int64_t& j) {
    i = std::min(bx - 1, std::max<std::int64_t>(0, static_cast<std::int64_t>((x - lo[0] + h) / bin)));
    j = std::min(by - 1, std::max<std::int64_t>(0, static_cast<std::int64_t>((y - lo[1]) / bin)));
  };
  for (std::size_t j = 0; j < n; ++j)
  {
    std::int64_t a, b;
    binOf(fx[j], fy[j], a, b);
    for (std::int64_t q = std::max<std::int64_t>(0, b - 1); q <= std::min(by - 1, b + 1); ++q)
    {
      for (std::int64_t p = std::max<std::int64_t>(0, a - 1); p <= std::min(bx - 1, a + 1); ++p)
      {
        near[static_cast<std::size_t>(q * bx + p)] = 1;
      }
    }
  }

  std::vector<double> uv;
  std::vector<std::int64_t> tris;
  std::vector<double> ta, tb;
  std::vector<std::int64_t> ia, ib;
  for (std::int64_t r = 0; r <= ny; ++r)
  {
    ta.swap(tb);
    ia.swap(ib);
    tb.clear();
    ib.clear();
    const double y = lo[1] + r * dy;
    const double x0 = (r % 2) ? lo[0] - 0.5 * h : lo[0];
    const std::int64_t count = (r % 2) ? nx + 1 : nx;
    for (std::int64_t i = 0; i <= count; ++i)
    {
      const double x = x0 + i * h;
      tb.push_back(x);
      ib.push_back(static_cast<std::int64_t>(uv.size() / 2));
      uv.push_back(x);
      uv.push_back(y);
    }
    if (r > 0)
    {
      Zip(ta, ia, tb, ib, tris);
    }
  }
  // Keep the triangles near the feet; renumber the used points.
  std::vector<std::int64_t> newId(uv.size() / 2, -1);
  mesh.Points.clear();
  mesh.Triangles.clear();
  for (std::size_t t = 0; t < tris.size(); t += 3)
  {
    bool keep = false;
    for (int c = 0; c < 3 && !keep; ++c)
    {
      std::int64_t a, b;
      binOf(uv[2 * tris[t + c]], uv[2 * tris[t + c] + 1], a, b);
      keep = near[static_cast<std::size_t>(b * bx + a)] != 0;
    }
    if (!keep)
    {
      continue;
    }
    for (int c = 0; c < 3; ++c)
    {
      const std::int64_t id = tris[t + c];
      if (newId[id] < 0)
      {
        newId[id] = static_cast<std::int64_t>(mesh.Points.size() / 3);
        const double x = uv[2 * id], y = uv[2 * id + 1];
        const double z = plane ? 0.0 : EvaluateGraph(degree, fit.Coefficients.data(), x, y).f;
        const Vec3 pw = f.ToWorld(Vec3(x, y, z));
        mesh.Points.insert(mesh.Points.end(), { pw[0], pw[1], pw[2] });
      }
      mesh.Triangles.push_back(newId[id]);
    }
  }
  return true;
}

bool TessellateCone(const SurfaceFitResult& fit, const double* points, std::size_t n, double h,
  double reach, SurfaceMesh& mesh, std::string& error, std::size_t maxTriangles)
{
  const Cone k = ResultCone(fit);
  const Frame f = FrameFromAxis(k.Apex, k.Axis);
  const double sinT = std::sin(k.Theta), cosT = std::cos(k.Theta);
  std::vector<double> phis(n);
  double smin = std::numeric_limits<double>::infinity(), smax = 0.0;
  for (std::size_t j = 0; j < n; ++j)
  {
    const Vec3 l = f.ToLocal(V3(points + 3 * j));
    const double rho = std::sqrt(l[0] * l[0] + l[1] * l[1]);
    const double s = std::max(0.0, l[2] * cosT + rho * sinT);
    smin = std::min(smin, s);
    smax = std::max(smax, s);
    phis[j] = std::atan2(l[1], l[0]);
  }
  const double pad = reach + h;
  const double sLo = std::max(0.0, smin - pad);
  const double sHi = smax + pad;

  // The angular range: the complement of the widest gap between the feet,
  // widened by `pad` at the smallest radius the feet reach; the whole circle
  // if that closes the gap.
  std::sort(phis.begin(), phis.end());
  double gap = phis.front() + 2.0 * Pi - phis.back();
  double gapEnd = phis.front(); // the arc starts where the widest gap ends
  for (std::size_t j = 1; j < n; ++j)
  {
    if (phis[j] - phis[j - 1] > gap)
    {
      gap = phis[j] - phis[j - 1];
      gapEnd = phis[j];
    }
  }
  const double rhoMin = std::max(smin * sinT, h);
  const double widen = pad / rhoMin;
  double span = 2.0 * Pi - gap + 2.0 * widen;
  const bool full = span >= 2.0 * Pi;
  const double phi0 = full ? 0.0 : gapEnd - widen;
  if (full)
  {
    span = 2.0 * Pi;
  }

  const double ds0 = h * std::sqrt(3.0) / 2.0;
  const double nsd = std::max(1.0, std::ceil((sHi - sLo) / ds0));
  const double area = span * 0.5 * (sHi * sHi - sLo * sLo) * sinT;
  if (TooMany(2.0 * area / (h * h * std::sqrt(3.0) / 2.0) + 4.0 * nsd, maxTriangles, error))
  {
    return false;
  }
  const std::int64_t ns = static_cast<std::int64_t>(nsd);
  const double ds = (sHi - sLo) / ns;

  mesh.Points.clear();
  mesh.Triangles.clear();
  auto addPoint = [&](double s, double phi) {
    const Vec3 l(s * sinT * std::cos(phi), s * sinT * std::sin(phi), s * cosT);
    const Vec3 pw = f.ToWorld(l);
    mesh.Points.insert(mesh.Points.end(), { pw[0], pw[1], pw[2] });
    return static_cast<std::int64_t>(mesh.Points.size() / 3 - 1);
  };
  std::vector<double> ta, tb;
  std::vector<std::int64_t> ia, ib;
  bool previousIsApex = false;
  for (std::int64_t r = 0; r <= ns; ++r)
  {
    ta.swap(tb);
    ia.swap(ib);
    tb.clear();
    ib.clear();
    const double s = sLo + r * ds;
    const double rho = s * sinT;
    if (r == 0 && s <= 1e-12 * sHi)
    {
      ib.push_back(addPoint(0.0, 0.0));
      tb.push_back(0.0);
      previousIsApex = true;
      continue;
    }
    if (full)
    {
      const std::int64_t m = std::max<std::int64_t>(3, std::llround(2.0 * Pi * rho / h));
      const double offset = (r % 2) ? 0.5 : 0.0;
      for (std::int64_t i = 0; i < m; ++i)
      {
        const double phi = phi0 + 2.0 * Pi * (i + offset) / m;
        tb.push_back(phi);
        ib.push_back(addPoint(s, phi));
      }
      tb.push_back(tb.front() + 2.0 * Pi); // closes the ring
      ib.push_back(ib.front());
    }
    else
    {
      const std::int64_t m = std::max<std::int64_t>(1, std::llround(span * rho / h));
      for (std::int64_t i = 0; i <= m; ++i)
      {
        const double phi = phi0 + span * i / m;
        tb.push_back(phi);
        ib.push_back(addPoint(s, phi));
      }
    }
    if (r == 0)
    {
      continue;
    }
    if (previousIsApex)
    {
      for (std::size_t i = 0; i + 1 < ib.size(); ++i)
      {
        mesh.Triangles.insert(mesh.Triangles.end(), { ia[0], ib[i + 1], ib[i] });
      }
      previousIsApex = false;
      continue;
    }
    Zip(ta, ia, tb, ib, mesh.Triangles);
  }
  return true;
}
}

bool TessellateSurface(const SurfaceFitResult& fit, const double* points, std::size_t n,
  double edgeLength, double reach, SurfaceMesh& mesh, std::string& error, std::size_t maxTriangles)
{
  mesh = SurfaceMesh();
  if (!(std::isfinite(edgeLength) && edgeLength > 0.0))
  {
    error = "The surface edge length must be positive and finite.";
    return false;
  }
  if (!(std::isfinite(reach) && reach >= 0.0))
  {
    error = "The margin must be zero or positive and finite.";
    return false;
  }
  if (n == 0 || !points)
  {
    error = "No points to mesh the surface around.";
    return false;
  }
  if (fit.Template == SurfaceTemplate::Cone)
  {
    return TessellateCone(fit, points, n, edgeLength, reach, mesh, error, maxTriangles);
  }
  return TessellateGraph(fit, points, n, edgeLength, reach, mesh, error, maxTriangles);
}
}

namespace ar
{
//------------------------------------------------------------------------------
bool FitSurfaceRobust(const double* points, const double* weights, std::size_t n,
  const SurfaceFitOptions& options, SurfaceFitResult& result, std::string& error, int iterations,
  std::vector<double>* robustWeights)
{
  // For the graphs (quadric, quartic) the reweighting runs on the cheap
  // vertical-offset fit; the geometric refinement runs once, on the final
  // weights. (The plane's refinement is an exact PCA; the cone's start needs it.)
  SurfaceFitOptions inner = options;
  const bool graph =
    options.Template == SurfaceTemplate::Quadric || options.Template == SurfaceTemplate::Quartic;
  if (graph)
  {
    inner.GeometricRefinement = false;
  }
  if (!FitSurface(points, weights, n, inner, result, error))
  {
    return false;
  }
  const double c = 4.685;
  std::vector<double> multiplier(n, 1.0), w(n), d(n), absd(n);
  const std::size_t minimum = SurfaceTemplateMinimumPoints(options.Template);
  for (int it = 0; it < iterations; ++it)
  {
    // The distances in units of each point's local mesh size l_j = 1 / w_j
    // (Eq. 4's weights): medial points scatter by a fraction of their own
    // cell, so on a mesh that grows along the feature one global scale
    // would reject the coarse part's good points and bias the fit.
    for (std::size_t j = 0; j < n; ++j)
    {
      const double l = weights ? 1.0 / weights[j] : 1.0;
      d[j] = SurfaceDistance(result, points + 3 * j) / l;
      absd[j] = std::abs(d[j]);
    }
    std::nth_element(absd.begin(), absd.begin() + n / 2, absd.end());
    const double s = 1.4826 * absd[n / 2];
    if (!(s > 0.0))
    {
      break; // more than half the points on the surface: nothing to downweight
    }
    std::size_t kept = 0;
    double change = 0.0;
    for (std::size_t j = 0; j < n; ++j)
    {
      const double u = d[j] / (c * s);
      const double m = std::abs(u) < 1.0 ? (1.0 - u * u) * (1.0 - u * u) : 0.0;
      change = std::max(change, std::abs(m - multiplier[j]));
      multiplier[j] = m;
      w[j] = (weights ? weights[j] : 1.0) * m;
      kept += m > 0.0 ? 1 : 0;
    }
    if (kept < minimum)
    {
      break;
    }
    // Zero weights are refused by FitSurface: keep only the points that count.
    std::vector<double> p2, w2;
    p2.reserve(3 * kept);
    w2.reserve(kept);
    for (std::size_t j = 0; j < n; ++j)
    {
      if (w[j] > 0.0)
      {
        p2.insert(p2.end(), points + 3 * j, points + 3 * j + 3);
        w2.push_back(w[j]);
      }
    }
    SurfaceFitResult refit;
    std::string refitError;
    if (!FitSurface(p2.data(), w2.data(), kept, inner, refit, refitError))
    {
      break; // keep the last good fit
    }
    result = refit;
    if (change < 0.02)
    {
      break;
    }
  }
  if (graph && options.GeometricRefinement)
  {
    std::vector<double> p2, w2;
    for (std::size_t j = 0; j < n; ++j)
    {
      const double wj = (weights ? weights[j] : 1.0) * multiplier[j];
      if (wj > 0.0)
      {
        p2.insert(p2.end(), points + 3 * j, points + 3 * j + 3);
        w2.push_back(wj);
      }
    }
    SurfaceFitResult refined;
    std::string refineError;
    if (w2.size() >= minimum &&
      FitSurface(p2.data(), w2.data(), w2.size(), options, refined, refineError))
    {
      result = refined;
    }
  }
  // Residuals over all the points.
  double sum = 0.0, wsum = 0.0, w2sum = 0.0;
  for (std::size_t j = 0; j < n; ++j)
  {
    const double dj = SurfaceDistance(result, points + 3 * j);
    const double wj = weights ? weights[j] : 1.0;
    sum += dj * dj;
    wsum += wj * wj * dj * dj;
    w2sum += wj * wj;
  }
  result.NumberOfPoints = n;
  result.RMSResidual = std::sqrt(sum / static_cast<double>(n));
  result.WeightedRMSResidual = w2sum > 0.0 ? std::sqrt(wsum / w2sum) : 0.0;
  if (robustWeights)
  {
    *robustWeights = multiplier;
  }
  return true;
}
bool FitSurfaceAutomatic(const double* points, const double* weights, std::size_t n,
  const SurfaceFitOptions& options, bool robust, double size, SurfaceFitResult& result, std::string& error,
  double residuals[4])
{
  const SurfaceTemplate order[4] = { SurfaceTemplate::Plane, SurfaceTemplate::Cone, SurfaceTemplate::Quadric,
    SurfaceTemplate::Quartic };
  SurfaceFitResult fits[4];
  bool ok[4] = { false, false, false, false };
  std::string why;
  // Points on two planes normal to a coordinate axis only (the medial points
  // of a one-cell-deep, 2-D mesh: its front and back nodes, as EmbeddedRemesh's
  // 2-D mode defines such a mesh) lie on two lines or curves. A cone
  // through them fits the two levels, not the shock: there the candidates are
  // the plane, the quadric and the quartic, extruded along that axis (z = f(x)
  // across it: a curved 2-D shock; a parabola through a whole bow shock
  // misses its vertex by a cell or two, the quartic by a fiftieth). In 3-D
  // the quartic's 15 coefficients follow the points' noise: not tried.
  int extrusionAxis = -1;
  for (int axis = 0; axis < 3 && extrusionAxis < 0 && n >= 4; ++axis)
  {
    double lo = std::numeric_limits<double>::max(), hi = -lo, span = 0.0;
    for (std::size_t j = 0; j < n; ++j)
    {
      lo = std::min(lo, points[3 * j + axis]);
      hi = std::max(hi, points[3 * j + axis]);
    }
    for (int other = 0; other < 3; ++other)
    {
      double a = std::numeric_limits<double>::max(), b = -a;
      for (std::size_t j = 0; j < n; ++j)
      {
        a = std::min(a, points[3 * j + other]);
        b = std::max(b, points[3 * j + other]);
      }
      span = std::max(span, b - a);
    }
    const double tol = 1e-9 * span;
    bool two = hi - lo > tol;
    for (std::size_t j = 0; j < n && two; ++j)
    {
      const double x = points[3 * j + axis];
      two = std::abs(x - lo) <= tol || std::abs(x - hi) <= tol;
    }
    extrusionAxis = two ? axis : -1;
  }
  const bool extruded = extrusionAxis >= 0;
  double best = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 4; ++k)
  {
    SurfaceFitOptions o = options;
    o.Template = order[k];
    std::fill(o.GraphAxis, o.GraphAxis + 3, 0.0); // the principal frame first (the graph axis below)
    if (extruded)
    {
      o.ExtrusionAxis = extrusionAxis; // (a caller's own axis stays otherwise)
    }
    const bool tried = extruded ? order[k] != SurfaceTemplate::Cone : order[k] != SurfaceTemplate::Quartic;
    std::string e;
    ok[k] = tried &&
      (robust ? FitSurfaceRobust(points, weights, n, o, fits[k], e) : FitSurface(points, weights, n, o, fits[k], e));
    if (tried && !ok[k])
    {
      why += std::string(why.empty() ? "" : "; ") + SurfaceTemplateName(order[k]) + ": " + e;
    }
    const double* axis = options.GraphAxis;
    if (order[k] == SurfaceTemplate::Quadric && !extruded && options.AutomaticAxis &&
      axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2] > 0.0)
    {
      // The quadric about the given axis too (FitGraph's frame through the
      // points' weighted centroid); the better of the two kept.
      std::copy(axis, axis + 3, o.GraphAxis);
      SurfaceFitResult about;
      std::string ignored;
      if ((robust ? FitSurfaceRobust(points, weights, n, o, about, ignored)
                  : FitSurface(points, weights, n, o, about, ignored)) &&
        (!ok[k] || about.RMSResidual < fits[k].RMSResidual))
      {
        fits[k] = about;
        ok[k] = true;
      }
    }
    if (residuals)
    {
      residuals[k] = ok[k] ? fits[k].RMSResidual : std::numeric_limits<double>::quiet_NaN();
    }
    if (ok[k])
    {
      best = std::min(best, fits[k].RMSResidual);
    }
  }
  if (!std::isfinite(best))
  {
    error = "no template could be fitted (" + why + ")";
    return false;
  }
  const double bound = AutomaticTemplateRatio * best + AutomaticTemplateSlack * std::max(size, 0.0);
  for (int k = 0; k < 4; ++k)
  {
    if (ok[k] && fits[k].RMSResidual <= bound)
    {
      result = fits[k];
      return true;
    }
  }
  error = "internal: no template within the bound"; // unreachable: the best one is within it
  return false;
}

//------------------------------------------------------------------------------
bool SplitDirectionFamilies(const double* directions, const double* weights, std::size_t n,
  DirectionFamilies& result)
{
  std::vector<Eigen::Vector3d> d;
  std::vector<double> w;
  d.reserve(n);
  w.reserve(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    const Eigen::Vector3d v(directions[3 * i], directions[3 * i + 1], directions[3 * i + 2]);
    const double len = v.norm();
    if (len > 0.0 && std::isfinite(len) && weights[i] > 0.0 && std::isfinite(weights[i]))
    {
      d.push_back(v / len);
      w.push_back(weights[i]);
    }
  }
  if (d.size() < 2)
  {
    return false;
  }
  // The principal axis (eigenvalues ascending) of a weighted scatter.
  auto principal = [](const Eigen::Matrix3d& scatter, Eigen::Vector3d& values, Eigen::Matrix3d& vectors) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(scatter);
    values = eig.eigenvalues();
    vectors = eig.eigenvectors();
  };
  Eigen::Matrix3d all = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < d.size(); ++i)
  {
    all += w[i] * d[i] * d[i].transpose();
  }
  Eigen::Vector3d values;
  Eigen::Matrix3d vectors;
  principal(all, values, vectors);
  // Two equal families at +-a about e1 in the (e1, e2) plane give the
  // scatter's two largest eigenvalues in the ratio cos^2 a : sin^2 a.
  const Eigen::Vector3d e1 = vectors.col(2), e2 = vectors.col(1);
  const double a = std::atan(std::sqrt(std::max(values(1), 0.0) / std::max(values(2), 1e-300)));
  Eigen::Vector3d axis[2] = { std::cos(a) * e1 + std::sin(a) * e2, std::cos(a) * e1 - std::sin(a) * e2 };
  std::vector<int> family(d.size(), -1);
  for (int iteration = 0; iteration < 100; ++iteration)
  {
    bool changed = false;
    Eigen::Matrix3d scatter[2] = { Eigen::Matrix3d::Zero(), Eigen::Matrix3d::Zero() };
    double mass[2] = { 0.0, 0.0 };
    for (std::size_t i = 0; i < d.size(); ++i)
    {
      const int f = std::abs(d[i].dot(axis[1])) > std::abs(d[i].dot(axis[0])) ? 1 : 0;
      changed = changed || f != family[i];
      family[i] = f;
      scatter[f] += w[i] * d[i] * d[i].transpose();
      mass[f] += w[i];
    }
    if (!changed)
    {
      break;
    }
    for (int f = 0; f < 2; ++f)
    {
      if (mass[f] > 0.0)
      {
        principal(scatter[f], values, vectors);
        axis[f] = vectors.col(2);
      }
    }
  }
  double mass[2] = { 0.0, 0.0 };
  std::vector<std::pair<double, double>> angles(d.size()); // (angle from the own axis, weight)
  for (std::size_t i = 0; i < d.size(); ++i)
  {
    mass[family[i]] += w[i];
    angles[i] = { std::acos(std::min(1.0, std::abs(d[i].dot(axis[family[i]])))), w[i] };
  }
  std::sort(angles.begin(), angles.end());
  const double total = mass[0] + mass[1];
  double below = 0.0, median = angles.back().first;
  for (const auto& aw : angles)
  {
    below += aw.second;
    if (below >= 0.5 * total)
    {
      median = aw.first;
      break;
    }
  }
  const double degrees = 180.0 / 3.14159265358979323846;
  for (int f = 0; f < 2; ++f)
  {
    for (int k = 0; k < 3; ++k)
    {
      result.Axes[f][k] = axis[f](k);
    }
  }
  result.AngleDegrees = std::acos(std::min(1.0, std::abs(axis[0].dot(axis[1])))) * degrees;
  result.SpreadDegrees = median * degrees;
  result.Fraction = std::min(mass[0], mass[1]) / total;
  return true;
}
}
