// Unit tests of the template fits of the VTK-free core (ARSurfaceFit): exact
// surfaces sampled with noise are recovered, the geometric refinement beats
// the vertical offsets of Eq. 4 on thick or steep point bands, the surface
// meshes are near-equilateral, and every bad input is refused with a message.
#include "ARSurfaceFit.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace
{
constexpr double Pi = 3.14159265358979323846;
using V = std::array<double, 3>;

V Add(const V& a, const V& b, double s = 1.0)
{
  return { a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2] };
}
double Dot(const V& a, const V& b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
V Cross(const V& a, const V& b)
{
  return { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0] };
}
V Unit(const V& a)
{
  const double n = std::sqrt(Dot(a, a));
  return { a[0] / n, a[1] / n, a[2] / n };
}
// The angle between two vectors as atan2(|a x b|, a . b), accurate to rounding
// at every angle (acos of a cosine next to 1 cannot resolve ~1e-6 degree).
double VectorAngleDeg(const V& a, const V& b)
{
  const V c = Cross(a, b);
  return std::atan2(std::sqrt(Dot(c, c)), Dot(a, b)) * 180.0 / Pi;
}
// The angle between two lines (0 to 90 degrees), whatever the directions' signs.
double AngleDeg(const V& a, const V& b)
{
  const double angle = VectorAngleDeg(a, b);
  return std::min(angle, 180.0 - angle);
}
double Distance(const V& a, const V& b)
{
  const V d = Add(a, b, -1.0);
  return std::sqrt(Dot(d, d));
}
/// Two unit vectors completing n to a right-handed frame.
void Perpendiculars(const V& n, V& e1, V& e2)
{
  const V a = std::abs(n[0]) < 0.9 ? V{ 1, 0, 0 } : V{ 0, 1, 0 };
  e1 = Unit(Cross(n, a));
  e2 = Cross(n, e1);
}

/// Points and weights (1 / local size) to fit.
struct Cloud
{
  std::vector<double> X;
  std::vector<double> W;
  void Add(const V& p, double w)
  {
    X.insert(X.end(), p.begin(), p.end());
    W.push_back(w);
  }
  std::size_t Size() const { return W.size(); }
};

ar::SurfaceFitResult Fit(const Cloud& c, ar::SurfaceTemplate t, bool refine = true,
  const V* origin = nullptr, const V* axis = nullptr)
{
  ar::SurfaceFitOptions o;
  o.Template = t;
  o.GeometricRefinement = refine;
  if (axis)
  {
    o.AutomaticAxis = false;
    std::copy(origin->begin(), origin->end(), o.AxisOrigin);
    std::copy(axis->begin(), axis->end(), o.AxisDirection);
  }
  ar::SurfaceFitResult r;
  std::string error;
  EXPECT_TRUE(ar::FitSurface(c.X.data(), c.W.data(), c.Size(), o, r, error)) << error;
  return r;
}

/// The plane through o with normal n, a 2 x 2 patch, Gaussian noise sigma
/// along n, local sizes in [0.5, 2].
Cloud PlaneCloud(const V& o, const V& n, double sigma, int count, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), size(0.5, 2.0);
  std::normal_distribution<double> noise(0.0, sigma);
  V e1, e2;
  Perpendiculars(Unit(n), e1, e2);
  Cloud c;
  for (int i = 0; i < count; ++i)
  {
    V p = Add(Add(o, e1, u(rng)), e2, u(rng));
    c.Add(Add(p, Unit(n), noise(rng)), 1.0 / size(rng));
  }
  return c;
}

/// A cone (apex a, axis d, half-angle theta): s in [s0, s1] along the
/// generators, phi in [phi0, phi1], noise along the surface normal.
Cloud ConeCloud(const V& a, const V& d, double thetaDeg, double s0, double s1, double phi0,
  double phi1, double sigma, int count, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> us(s0, s1), uphi(phi0, phi1), size(0.5, 2.0);
  std::normal_distribution<double> noise(0.0, sigma);
  const double th = thetaDeg * Pi / 180.0;
  V e1, e2;
  const V z = Unit(d);
  Perpendiculars(z, e1, e2);
  Cloud c;
  for (int i = 0; i < count; ++i)
  {
    const double s = us(rng), phi = uphi(rng);
    const V radial = Add(Add(V{ 0, 0, 0 }, e1, std::cos(phi)), e2, std::sin(phi));
    const V g = Add(Add(V{ 0, 0, 0 }, z, std::cos(th)), radial, std::sin(th));
    const V normal = Add(Add(V{ 0, 0, 0 }, radial, std::cos(th)), z, -std::sin(th));
    c.Add(Add(Add(a, g, s), normal, noise(rng)), 1.0 / size(rng));
  }
  return c;
}

/// The frame the core builds from a user axis: x along the coordinate axis
/// least aligned with z.
void UserFrame(const V& axis, V& x, V& y, V& z)
{
  z = Unit(axis);
  int k = 0;
  for (int i = 1; i < 3; ++i)
  {
    if (std::abs(z[i]) < std::abs(z[k]))
    {
      k = i;
    }
  }
  V e{ 0, 0, 0 };
  e[k] = 1.0;
  x = Unit(Add(e, z, -Dot(e, z)));
  y = Cross(z, x);
}

double Polynomial(int degree, const std::vector<double>& c, double x, double y)
{
  double f = 0.0;
  int k = 0;
  for (int d = 0; d <= degree; ++d)
  {
    for (int i = d; i >= 0; --i)
    {
      f += c[k++] * std::pow(x, i) * std::pow(y, d - i);
    }
  }
  return f;
}

/// Samples z = f(x, y) in the user frame of (origin, axis) over [-r, r]^2,
/// noise along the surface normal (Gaussian sigma, or uniform +-band).
Cloud GraphCloud(const V& origin, const V& axis, int degree, const std::vector<double>& c,
  double r, double sigma, double band, int count, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-r, r), size(0.5, 2.0), thick(-band, band);
  std::normal_distribution<double> noise(0.0, sigma);
  V X, Y, Z;
  UserFrame(axis, X, Y, Z);
  Cloud cloud;
  const double h = 1e-6;
  for (int i = 0; i < count; ++i)
  {
    const double x = u(rng), y = u(rng);
    const double f = Polynomial(degree, c, x, y);
    const double fx = (Polynomial(degree, c, x + h, y) - Polynomial(degree, c, x - h, y)) / (2 * h);
    const double fy = (Polynomial(degree, c, x, y + h) - Polynomial(degree, c, x, y - h)) / (2 * h);
    const V nl = Unit(V{ -fx, -fy, 1.0 });
    const double off = (sigma > 0.0 ? noise(rng) : 0.0) + (band > 0.0 ? thick(rng) : 0.0);
    const V local{ x + off * nl[0], y + off * nl[1], f + off * nl[2] };
    V p = Add(Add(Add(origin, X, local[0]), Y, local[1]), Z, local[2]);
    cloud.Add(p, 1.0 / size(rng));
  }
  return cloud;
}

double MaxRelativeError(const std::vector<double>& got, const std::vector<double>& want)
{
  double e = 0.0;
  for (std::size_t k = 0; k < want.size(); ++k)
  {
    e = std::max(e, std::abs(got[k] - want[k]) / std::abs(want[k]));
  }
  return e;
}

/// Smallest angle (degrees) over the triangles of a mesh.
double MinimumAngle(const ar::SurfaceMesh& m)
{
  double worst = 180.0;
  for (std::size_t t = 0; t < m.Triangles.size(); t += 3)
  {
    V p[3];
    for (int c = 0; c < 3; ++c)
    {
      const double* x = &m.Points[3 * m.Triangles[t + c]];
      p[c] = { x[0], x[1], x[2] };
    }
    for (int c = 0; c < 3; ++c)
    {
      const V a = Add(p[(c + 1) % 3], p[c], -1.0), b = Add(p[(c + 2) % 3], p[c], -1.0);
      worst = std::min(worst, VectorAngleDeg(a, b));
    }
  }
  return worst;
}

std::string Refusal(const Cloud& c, ar::SurfaceTemplate t, bool automatic = true,
  V axis = { 0, 0, 1 }, const double* weights = nullptr)
{
  ar::SurfaceFitOptions o;
  o.Template = t;
  o.AutomaticAxis = automatic;
  std::copy(axis.begin(), axis.end(), o.AxisDirection);
  ar::SurfaceFitResult r;
  std::string error;
  EXPECT_FALSE(ar::FitSurface(c.X.data(), weights ? weights : c.W.data(), c.Size(), o, r, error));
  return error;
}
}

//------------------------------------------------------------------------------
TEST(SurfaceFit, PlaneNormalRecovered)
{
  const V n = Unit({ 0.3, -0.5, 0.8 }), o{ 0.2, 0.4, -0.1 };
  const Cloud c = PlaneCloud(o, n, 0.01, 2000, 1);
  for (bool automatic : { true, false })
  {
    const V axis{ 0, 0, 1 };
    const ar::SurfaceFitResult r = automatic ? Fit(c, ar::SurfaceTemplate::Plane)
                                             : Fit(c, ar::SurfaceTemplate::Plane, true, &o, &axis);
    const V got{ r.Normal[0], r.Normal[1], r.Normal[2] };
    const double angle = AngleDeg(got, n);
    RecordProperty(automatic ? "PlaneAngleAutoDeg" : "PlaneAngleUserDeg", std::to_string(angle));
    std::printf("plane (%s axis): normal error %.4f deg, RMS %.5f\n", automatic ? "automatic" : "user", angle, r.RMSResidual);
    EXPECT_LT(angle, 0.2) << "normal off by " << angle << " deg";
    EXPECT_NEAR(Dot(Add(V{ r.Origin[0], r.Origin[1], r.Origin[2] }, o, -1.0), n), 0.0, 2e-3);
    EXPECT_NEAR(r.RMSResidual, 0.01, 1.5e-3);
    ASSERT_EQ(r.Coefficients.size(), 4u);
    // a x + b y + c z + d = 0 holds at the true origin.
    EXPECT_NEAR(r.Coefficients[0] * o[0] + r.Coefficients[1] * o[1] + r.Coefficients[2] * o[2] +
        r.Coefficients[3], 0.0, 2e-3);
  }
}

TEST(SurfaceFit, ConeRecoveredWithAutomaticAxis)
{
  const V apex{ 0.1, 0.2, -0.3 }, axis = Unit({ 1.0, 0.2, 0.1 });
  struct Case
  {
    const char* Name;
    double Theta, Phi0, Phi1;
  };
  // A full cone, half of one (a symmetry plane), a quarter, a wide one.
  for (const Case& k : { Case{ "full", 25.0, -Pi, Pi }, Case{ "half", 30.0, 0.0, Pi },
         Case{ "quarter", 20.0, 0.3, 0.3 + 0.5 * Pi }, Case{ "wide", 60.0, -Pi, Pi } })
  {
    const Cloud c = ConeCloud(apex, axis, k.Theta, 1.0, 3.0, k.Phi0, k.Phi1, 0.005, 3000, 2);
    const ar::SurfaceFitResult r = Fit(c, ar::SurfaceTemplate::Cone);
    const double dTheta = std::abs(r.HalfAngleDegrees - k.Theta);
    const double dAxis = AngleDeg({ r.AxisDirection[0], r.AxisDirection[1], r.AxisDirection[2] }, axis);
    const double dApex = Distance({ r.Apex[0], r.Apex[1], r.Apex[2] }, apex);
    RecordProperty(std::string("ConeHalfAngleErrorDeg_") + k.Name, std::to_string(dTheta));
    std::printf("cone %s (%.0f deg): half-angle error %.4f deg, axis %.4f deg, apex %.5f, RMS %.5f, %d iterations\n",
      k.Name, k.Theta, dTheta, dAxis, dApex, r.RMSResidual, r.Iterations);
    EXPECT_LT(dTheta, 0.2) << k.Name << ": half-angle " << r.HalfAngleDegrees;
    EXPECT_LT(dAxis, 0.3) << k.Name;
    EXPECT_LT(dApex, 0.02) << k.Name;
    EXPECT_GT(Dot({ r.AxisDirection[0], r.AxisDirection[1], r.AxisDirection[2] }, axis), 0.0)
      << k.Name << ": the axis points into the nappe";
    EXPECT_NEAR(r.RMSResidual, 0.005, 1e-3) << k.Name;
    ASSERT_EQ(r.Coefficients.size(), 7u);
    EXPECT_DOUBLE_EQ(r.Coefficients[6], r.HalfAngleDegrees);
    // Eq. 4 alone, about the axis the general quadric gives: close, not as close.
    const ar::SurfaceFitResult v = Fit(c, ar::SurfaceTemplate::Cone, false);
    const double dThetaV = std::abs(v.HalfAngleDegrees - k.Theta);
    std::printf("cone %s, Eq. 4 only: half-angle error %.4f deg, RMS %.5f\n", k.Name, dThetaV, v.RMSResidual);
    EXPECT_LT(dThetaV, 1.0) << k.Name;
    EXPECT_GE(v.RMSResidual, r.RMSResidual * (1.0 - 1e-9)) << k.Name;
  }
}

TEST(SurfaceFit, ConeFromAnApproximateUserAxis)
{
  const V apex{ -0.2, 0.5, 0.5 }, axis{ 1, 0, 0 };
  const Cloud c = ConeCloud(apex, axis, 35.0, 0.5, 1.5, -Pi, Pi, 0.003, 2000, 3);
  // The user's axis: 6 degrees off and through a point 0.05 off the true axis.
  const V userAxis = Unit({ 1.0, std::tan(6.0 * Pi / 180.0), 0.0 });
  const V userOrigin{ -0.2, 0.55, 0.5 };
  const ar::SurfaceFitResult refined = Fit(c, ar::SurfaceTemplate::Cone, true, &userOrigin, &userAxis);
  std::printf("cone from a 6 deg-off user axis: half-angle error %.4f deg, apex %.5f\n",
    std::abs(refined.HalfAngleDegrees - 35.0), Distance({ refined.Apex[0], refined.Apex[1], refined.Apex[2] }, apex));
  EXPECT_LT(std::abs(refined.HalfAngleDegrees - 35.0), 0.2);
  EXPECT_LT(AngleDeg({ refined.AxisDirection[0], refined.AxisDirection[1], refined.AxisDirection[2] }, axis), 0.3);
  EXPECT_LT(Distance({ refined.Apex[0], refined.Apex[1], refined.Apex[2] }, apex), 0.01);
  // Eq. 4 alone keeps the user's axis line: its residual is far larger.
  const ar::SurfaceFitResult vertical = Fit(c, ar::SurfaceTemplate::Cone, false, &userOrigin, &userAxis);
  EXPECT_NEAR(AngleDeg({ vertical.AxisDirection[0], vertical.AxisDirection[1], vertical.AxisDirection[2] }, userAxis), 0.0, 1e-9);
  EXPECT_GT(vertical.RMSResidual, 5.0 * refined.RMSResidual);
  EXPECT_FALSE(vertical.Refined);
  EXPECT_TRUE(refined.Refined);
}

TEST(SurfaceFit, QuadricCoefficientsRecovered)
{
  const V origin{ 0.5, -0.2, 0.1 }, axis = Unit({ 0.2, 0.1, 1.0 });
  const std::vector<double> c = { 0.3, 0.2, -0.1, 0.4, 0.25, -0.3 };
  const Cloud cloud = GraphCloud(origin, axis, 2, c, 1.0, 0.001, 0.0, 3000, 4);
  for (bool refine : { false, true })
  {
    const ar::SurfaceFitResult r = Fit(cloud, ar::SurfaceTemplate::Quadric, refine, &origin, &axis);
    ASSERT_EQ(r.Coefficients.size(), 6u);
    const double e = MaxRelativeError(r.Coefficients, c);
    RecordProperty(refine ? "QuadricCoefficientErrorRefined" : "QuadricCoefficientErrorVertical",
      std::to_string(e));
    std::printf("quadric (%s): largest relative coefficient error %.5f\n", refine ? "refined" : "vertical", e);
    EXPECT_LT(e, 0.01) << (refine ? "refined" : "vertical");
    EXPECT_NEAR(r.RMSResidual, 0.001, 2e-4);
  }
}

TEST(SurfaceFit, QuarticRecovered)
{
  const V origin{ 0, 0, 0 }, axis{ 0, 0, 1 };
  const std::vector<double> c = { 0.1, 0.05, -0.02, 0.2, -0.1, 0.15, 0.03, -0.05, 0.02, 0.04,
    -0.06, 0.03, 0.05, -0.02, 0.04 };
  const Cloud cloud = GraphCloud(origin, axis, 4, c, 1.0, 0.0005, 0.0, 4000, 5);
  const ar::SurfaceFitResult r = Fit(cloud, ar::SurfaceTemplate::Quartic, true, &origin, &axis);
  ASSERT_EQ(r.Coefficients.size(), 15u);
  double worst = 0.0;
  for (std::size_t k = 0; k < c.size(); ++k)
  {
    worst = std::max(worst, std::abs(r.Coefficients[k] - c[k]));
  }
  std::printf("quartic: largest absolute coefficient error %.5f\n", worst);
  EXPECT_LT(worst, 0.005);
  EXPECT_NEAR(r.RMSResidual, 0.0005, 1e-4);
  // And with the automatic (principal) frame the surface is the same.
  const ar::SurfaceFitResult a = Fit(cloud, ar::SurfaceTemplate::Quartic);
  EXPECT_NEAR(a.RMSResidual, 0.0005, 1e-4);
}

TEST(SurfaceFit, RefinementBeatsVerticalOffsetsOnATiltedThickBand)
{
  // A plane whose normal is 50 degrees from the user's axis; the points fill
  // a band +-0.15 thick (a coarse, thick shock region).
  const V n = Unit({ std::sin(50.0 * Pi / 180.0), 0.0, std::cos(50.0 * Pi / 180.0) });
  const V o{ 0, 0, 0 }, axis{ 0, 0, 1 };
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> u(-1.0, 1.0), band(-0.15, 0.15);
  V e1, e2;
  Perpendiculars(n, e1, e2);
  Cloud c;
  for (int i = 0; i < 3000; ++i)
  {
    c.Add(Add(Add(Add(o, e1, u(rng)), e2, u(rng)), n, band(rng)), 1.0);
  }
  const ar::SurfaceFitResult vertical = Fit(c, ar::SurfaceTemplate::Plane, false, &o, &axis);
  const ar::SurfaceFitResult refined = Fit(c, ar::SurfaceTemplate::Plane, true, &o, &axis);
  const double av = AngleDeg({ vertical.Normal[0], vertical.Normal[1], vertical.Normal[2] }, n);
  const double ar_ = AngleDeg({ refined.Normal[0], refined.Normal[1], refined.Normal[2] }, n);
  RecordProperty("ThickBandVerticalDeg", std::to_string(av));
  RecordProperty("ThickBandRefinedDeg", std::to_string(ar_));
  std::printf("tilted thick band: normal error vertical %.3f deg, refined %.3f deg\n", av, ar_);
  EXPECT_GT(av, 1.0) << "vertical offsets should be biased on a thick tilted band";
  EXPECT_LT(ar_, 0.3);
  EXPECT_LT(refined.RMSResidual, vertical.RMSResidual);
}

TEST(SurfaceFit, RefinementBeatsVerticalOffsetsOnASteepQuadric)
{
  const V origin{ 0, 0, 0 }, axis{ 0, 0, 1 };
  const std::vector<double> c = { 0.0, 0.0, 0.0, 0.8, 0.0, 0.8 };
  const Cloud cloud = GraphCloud(origin, axis, 2, c, 1.5, 0.0, 0.15, 4000, 7);
  const ar::SurfaceFitResult vertical = Fit(cloud, ar::SurfaceTemplate::Quadric, false, &origin, &axis);
  const ar::SurfaceFitResult refined = Fit(cloud, ar::SurfaceTemplate::Quadric, true, &origin, &axis);
  // Error of the curvature terms (x^2, y^2).
  const double ev = std::max(std::abs(vertical.Coefficients[3] - 0.8), std::abs(vertical.Coefficients[5] - 0.8));
  const double er = std::max(std::abs(refined.Coefficients[3] - 0.8), std::abs(refined.Coefficients[5] - 0.8));
  RecordProperty("SteepQuadricVerticalError", std::to_string(ev));
  RecordProperty("SteepQuadricRefinedError", std::to_string(er));
  std::printf("steep quadric: x^2, y^2 coefficient error vertical %.4f, refined %.4f (of 0.8)\n", ev, er);
  EXPECT_GT(ev, 0.02);
  EXPECT_LT(er, 0.01);
  EXPECT_LT(er, 0.25 * ev);
  EXPECT_LT(refined.RMSResidual, vertical.RMSResidual);
  EXPECT_GT(refined.Iterations, 0);
}

TEST(SurfaceFit, DistanceAndProjectionAgree)
{
  const V apex{ 0, 0, 0 }, axis{ 0, 0, 1 };
  const Cloud cone = ConeCloud(apex, axis, 30.0, 1.0, 2.0, -Pi, Pi, 0.01, 500, 8);
  const V origin{ 0, 0, 0 };
  const Cloud quad = GraphCloud(origin, axis, 2, { 0.0, 0.1, 0.0, 0.5, 0.1, -0.4 }, 1.0, 0.02, 0.0, 500, 9);
  for (const auto& item : { std::make_pair(&cone, ar::SurfaceTemplate::Cone),
         std::make_pair(&quad, ar::SurfaceTemplate::Quadric) })
  {
    const ar::SurfaceFitResult r = Fit(*item.first, item.second);
    for (std::size_t j = 0; j < item.first->Size(); j += 25)
    {
      const double* p = &item.first->X[3 * j];
      double foot[3];
      ar::ProjectOntoSurface(r, p, foot);
      EXPECT_NEAR(ar::SurfaceDistance(r, foot), 0.0, 1e-9);
      EXPECT_NEAR(std::abs(ar::SurfaceDistance(r, p)),
        Distance({ p[0], p[1], p[2] }, { foot[0], foot[1], foot[2] }), 1e-9);
    }
  }
}

TEST(SurfaceFit, MeshesAreNearEquilateralAndCoverTheFeet)
{
  const V apex{ 0, 0, 0 }, axis = Unit({ 1, 1, 0 });
  struct Case
  {
    const char* Name;
    Cloud C;
    ar::SurfaceTemplate T;
    double MinAngle;
  };
  std::vector<Case> cases;
  cases.push_back({ "plane", PlaneCloud({ 0, 0, 0 }, Unit({ 1, 2, 3 }), 0.0, 400, 10),
    ar::SurfaceTemplate::Plane, 59.9 });
  cases.push_back({ "cone", ConeCloud(apex, axis, 30.0, 1.0, 2.0, -Pi, Pi, 0.0, 800, 11),
    ar::SurfaceTemplate::Cone, 35.0 });
  cases.push_back({ "half cone", ConeCloud(apex, axis, 40.0, 1.0, 2.0, 0.0, Pi, 0.0, 800, 12),
    ar::SurfaceTemplate::Cone, 35.0 });
  cases.push_back({ "quadric", GraphCloud({ 0, 0, 0 }, { 0, 0, 1 }, 2, { 0, 0, 0, 0.1, 0, 0.1 }, 1.0, 0.0, 0.0, 400, 13),
    ar::SurfaceTemplate::Quadric, 40.0 });
  const double h = 0.05, reach = 0.1;
  for (const Case& k : cases)
  {
    const ar::SurfaceFitResult r = Fit(k.C, k.T);
    ar::SurfaceMesh mesh;
    std::string error;
    ASSERT_TRUE(ar::TessellateSurface(r, k.C.X.data(), k.C.Size(), h, reach, mesh, error)) << error;
    ASSERT_GT(mesh.Triangles.size(), 0u);
    EXPECT_GT(MinimumAngle(mesh), k.MinAngle) << k.Name;
    // The points lie on the surface.
    double off = 0.0;
    for (std::size_t i = 0; i < mesh.Points.size(); i += 3)
    {
      off = std::max(off, std::abs(ar::SurfaceDistance(r, &mesh.Points[i])));
    }
    EXPECT_LT(off, 1e-9) << k.Name;
    // Mean edge length near h.
    double sum = 0.0;
    for (std::size_t t = 0; t < mesh.Triangles.size(); t += 3)
    {
      for (int c = 0; c < 3; ++c)
      {
        const double* a = &mesh.Points[3 * mesh.Triangles[t + c]];
        const double* b = &mesh.Points[3 * mesh.Triangles[t + (c + 1) % 3]];
        sum += Distance({ a[0], a[1], a[2] }, { b[0], b[1], b[2] });
      }
    }
    const double mean = sum / static_cast<double>(mesh.Triangles.size());
    EXPECT_NEAR(mean, h, 0.1 * h) << k.Name;
    // Every point's foot, and the margin around it, is covered: a mesh
    // point within h of the foot displaced by `reach` along the surface is
    // hard to test in general; check the foot itself is within h of a point.
    for (std::size_t j = 0; j < k.C.Size(); j += 7)
    {
      double foot[3];
      ar::ProjectOntoSurface(r, &k.C.X[3 * j], foot);
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < mesh.Points.size(); i += 3)
      {
        best = std::min(best, Distance({ foot[0], foot[1], foot[2] },
                                { mesh.Points[i], mesh.Points[i + 1], mesh.Points[i + 2] }));
      }
      EXPECT_LT(best, h) << k.Name;
    }
  }
}

TEST(SurfaceFit, ConeMeshReachesTheApex)
{
  const V apex{ 0, 0, 0 }, axis{ 0, 0, 1 };
  const Cloud c = ConeCloud(apex, axis, 30.0, 0.0, 1.0, -Pi, Pi, 0.0, 600, 14);
  const ar::SurfaceFitResult r = Fit(c, ar::SurfaceTemplate::Cone);
  ar::SurfaceMesh mesh;
  std::string error;
  ASSERT_TRUE(ar::TessellateSurface(r, c.X.data(), c.Size(), 0.05, 0.1, mesh, error)) << error;
  EXPECT_NEAR(Distance({ mesh.Points[0], mesh.Points[1], mesh.Points[2] }, apex), 0.0, 1e-6);
  EXPECT_GT(MinimumAngle(mesh), 15.0);
}

TEST(SurfaceFit, BadInputIsRefused)
{
  const Cloud plane = PlaneCloud({ 0, 0, 0 }, { 0, 0, 1 }, 0.01, 50, 15);
  auto head = [](const Cloud& c, std::size_t n) {
    Cloud h;
    h.X.assign(c.X.begin(), c.X.begin() + 3 * n);
    h.W.assign(c.W.begin(), c.W.begin() + n);
    return h;
  };
  EXPECT_NE(Refusal(head(plane, 2), ar::SurfaceTemplate::Plane).find("Too few points: the Plane needs at least 3"), std::string::npos);
  EXPECT_NE(Refusal(head(plane, 5), ar::SurfaceTemplate::Quadric).find("needs at least 6"), std::string::npos);
  EXPECT_NE(Refusal(head(plane, 14), ar::SurfaceTemplate::Quartic).find("needs at least 15"), std::string::npos);
  EXPECT_NE(Refusal(head(plane, 5), ar::SurfaceTemplate::Cone).find("needs at least 6"), std::string::npos);
  const Cloud cone = ConeCloud({ 0, 0, 0 }, { 0, 0, 1 }, 30.0, 1.0, 2.0, -Pi, Pi, 0.0, 40, 16);
  EXPECT_NE(Refusal(head(cone, 8), ar::SurfaceTemplate::Cone).find("at least 10 points"), std::string::npos);

  Cloud nan = plane;
  nan.X[3 * 7 + 1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(Refusal(nan, ar::SurfaceTemplate::Plane).find("Point 7 has a NaN"), std::string::npos);
  Cloud inf = plane;
  inf.X[3 * 9] = std::numeric_limits<double>::infinity();
  EXPECT_NE(Refusal(inf, ar::SurfaceTemplate::Cone).find("Point 9 has a NaN or infinite"), std::string::npos);
  Cloud badWeight = plane;
  badWeight.W[3] = 0.0;
  EXPECT_NE(Refusal(badWeight, ar::SurfaceTemplate::Plane).find("weight of point 3 is 0"), std::string::npos);
  badWeight.W[3] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(Refusal(badWeight, ar::SurfaceTemplate::Quadric).find("weight of point 3"), std::string::npos);

  EXPECT_NE(Refusal(plane, ar::SurfaceTemplate::Plane, false, { 0, 0, 0 }).find("Degenerate axis"), std::string::npos);
  EXPECT_NE(Refusal(plane, ar::SurfaceTemplate::Cone, false, { 0, 0, 0 }).find("Degenerate axis"), std::string::npos);
  EXPECT_NE(Refusal(plane, ar::SurfaceTemplate::Quadric, false, { 0, std::nan(""), 1 }).find("NaN"), std::string::npos);

  Cloud line;
  for (int i = 0; i < 20; ++i)
  {
    line.Add({ 0.1 * i, 0.2 * i, -0.05 * i }, 1.0);
  }
  EXPECT_NE(Refusal(line, ar::SurfaceTemplate::Plane).find("collinear"), std::string::npos);
  EXPECT_NE(Refusal(line, ar::SurfaceTemplate::Cone).find("collinear"), std::string::npos);
  Cloud same;
  for (int i = 0; i < 20; ++i)
  {
    same.Add({ 1, 2, 3 }, 1.0);
  }
  EXPECT_NE(Refusal(same, ar::SurfaceTemplate::Quadric).find("coincide"), std::string::npos);

  // Exactly coplanar points (a tilted plane) cannot make a cone.
  const Cloud flat = PlaneCloud({ 0, 0, 0 }, Unit({ 1, 1, 1 }), 0.0, 100, 17);
  EXPECT_NE(Refusal(flat, ar::SurfaceTemplate::Cone).find("coplanar"), std::string::npos);
  EXPECT_NE(Refusal(flat, ar::SurfaceTemplate::Cone, false, { 0, 0, 1 }).find("coplanar"), std::string::npos);

  // Singular systems: points on the plane x = y, fitted along z, project
  // onto a line of the (x, y) plane.
  Cloud wall;
  std::mt19937 rng(18);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 60; ++i)
  {
    const double t = u(rng);
    wall.Add({ t, t, u(rng) }, 1.0);
  }
  EXPECT_NE(Refusal(wall, ar::SurfaceTemplate::Quadric, false, { 0, 0, 1 }).find("Singular system"), std::string::npos);
  EXPECT_NE(Refusal(wall, ar::SurfaceTemplate::Plane, false, { 0, 0, 1 }).find("Singular system"), std::string::npos);
  // Any axis lying in the wall: every point projects onto one line.
  EXPECT_NE(Refusal(wall, ar::SurfaceTemplate::Quartic, false, { 1, 1, 0 }).find("Singular system"), std::string::npos);

  // A cylinder (no cone about its axis: the radius does not vary).
  Cloud cylinder;
  for (int i = 0; i < 200; ++i)
  {
    const double phi = 2 * Pi * i / 200.0;
    cylinder.Add({ std::cos(phi), std::sin(phi), (i % 10) * 0.1 }, 1.0);
  }
  EXPECT_NE(Refusal(cylinder, ar::SurfaceTemplate::Cone, false, { 0, 0, 1 }).find("No cone fits"), std::string::npos);

  // Tessellation arguments.
  const ar::SurfaceFitResult r = Fit(plane, ar::SurfaceTemplate::Plane);
  ar::SurfaceMesh mesh;
  std::string error;
  EXPECT_FALSE(ar::TessellateSurface(r, plane.X.data(), plane.Size(), 0.0, 0.1, mesh, error));
  EXPECT_NE(error.find("edge length"), std::string::npos);
  EXPECT_FALSE(ar::TessellateSurface(r, plane.X.data(), plane.Size(), 1e-5, 0.1, mesh, error));
  EXPECT_NE(error.find("too small"), std::string::npos);
}

TEST(SurfaceFit, RobustFitIgnoresAWallCutBranch)
{
  // A plane with noise 0.005, plus 15% of the points on a second, tilted
  // branch (as medial points on a wall that cuts a shock band): the plain fit
  // is pulled off, Tukey's biweight recovers the plane and gives the branch
  // zero weight.
  const V n = Unit({ 0.4, -0.9, 0.1 }), o{ 0.0, 0.0, 0.0 };
  Cloud c = PlaneCloud(o, n, 0.005, 1700, 11);
  const V m = Unit({ 0.1, -1.0, 0.0 });
  const Cloud branch = PlaneCloud(Add(o, n, 0.05), m, 0.002, 300, 12);
  for (std::size_t j = 0; j < branch.Size(); ++j)
  {
    c.Add({ branch.X[3 * j], branch.X[3 * j + 1], branch.X[3 * j + 2] }, branch.W[j]);
  }
  ar::SurfaceFitOptions o2;
  o2.Template = ar::SurfaceTemplate::Plane;
  ar::SurfaceFitResult plain, robust;
  std::string error;
  ASSERT_TRUE(ar::FitSurface(c.X.data(), c.W.data(), c.Size(), o2, plain, error)) << error;
  std::vector<double> multipliers;
  ASSERT_TRUE(ar::FitSurfaceRobust(c.X.data(), c.W.data(), c.Size(), o2, robust, error, 10, &multipliers))
    << error;
  const double plainAngle = AngleDeg({ plain.Normal[0], plain.Normal[1], plain.Normal[2] }, n);
  const double robustAngle = AngleDeg({ robust.Normal[0], robust.Normal[1], robust.Normal[2] }, n);
  std::printf("plane with a 15%% branch: plain fit %.3f deg off, robust fit %.3f deg off\n", plainAngle, robustAngle);
  EXPECT_GT(plainAngle, 1.0);
  EXPECT_LT(robustAngle, 0.2);
  ASSERT_EQ(multipliers.size(), c.Size());
  std::size_t rejected = 0;
  for (std::size_t j = 1700; j < c.Size(); ++j)
  {
    rejected += multipliers[j] < 0.1 ? 1 : 0;
  }
  EXPECT_GT(rejected, 250u); // most of the branch, which lies 0.05 and more off the plane

  // On clean data the robust fit is the plain fit.
  const Cloud clean = PlaneCloud(o, n, 0.005, 2000, 13);
  ASSERT_TRUE(ar::FitSurface(clean.X.data(), clean.W.data(), clean.Size(), o2, plain, error));
  ASSERT_TRUE(ar::FitSurfaceRobust(clean.X.data(), clean.W.data(), clean.Size(), o2, robust, error));
  EXPECT_LT(AngleDeg({ plain.Normal[0], plain.Normal[1], plain.Normal[2] },
              { robust.Normal[0], robust.Normal[1], robust.Normal[2] }), 0.05);
}

TEST(SurfaceFit, AutomaticTemplatePicksTheShape)
{
  // Noise 0.005 on points whose local mesh size is 0.02 (a shock's medial
  // points scatter by a fraction of a cell): each shape gets its template.
  const double size = 0.02;
  auto automatic = [&](const Cloud& c, ar::SurfaceFitResult& r, double residuals[4]) {
    ar::SurfaceFitOptions o;
    std::string error;
    const bool ok = ar::FitSurfaceAutomatic(c.X.data(), c.W.data(), c.Size(), o, true, size, r, error, residuals);
    EXPECT_TRUE(ok) << error;
    std::printf("automatic: %s (residuals plane %.5f, cone %.5f, quadric %.5f)\n", ar::SurfaceTemplateName(r.Template),
      residuals[0], residuals[1], residuals[2]);
  };
  double res[4]; // FitSurfaceAutomatic writes all four (plane, cone, quadric, quartic)
  ar::SurfaceFitResult r;
  const V n = Unit({ 0.3, -0.2, 1.0 });
  automatic(PlaneCloud({ 0.1, 0.2, 0.3 }, n, 0.005, 2000, 7), r, res);
  EXPECT_EQ(r.Template, ar::SurfaceTemplate::Plane);
  EXPECT_LT(AngleDeg({ r.Normal[0], r.Normal[1], r.Normal[2] }, n), 0.2);
  EXPECT_LE(r.RMSResidual, ar::AutomaticTemplateRatio * std::min({ res[0], res[1], res[2] }) +
      ar::AutomaticTemplateSlack * size);

  const V apex{ 0.1, 0.2, -0.3 }, axis = Unit({ 1.0, 0.2, 0.1 });
  automatic(ConeCloud(apex, axis, 30.0, 1.0, 3.0, 0.0, Pi, 0.005, 3000, 2), r, res);
  EXPECT_EQ(r.Template, ar::SurfaceTemplate::Cone);
  EXPECT_NEAR(r.HalfAngleDegrees, 30.0, 0.2);
  EXPECT_GT(res[0], 10.0 * res[1]) << "the plane does not fit a cone";

  // A paraboloid cap, as a bow shock's vertex region.
  const V origin{ 0.0, 0.0, 0.0 }, z = Unit({ -1.0, 0.1, 0.0 });
  automatic(GraphCloud(origin, z, 2, { 0.0, 0.0, 0.0, 0.5, 0.0, 0.5 }, 1.0, 0.005, 0.0, 3000, 5), r, res);
  EXPECT_EQ(r.Template, ar::SurfaceTemplate::Quadric);
  EXPECT_GT(res[1], 2.0 * res[2]) << "a cone does not fit a paraboloid's vertex";

  // Too few points for any template: every failure is named.
  Cloud two;
  two.Add({ 0, 0, 0 }, 1.0);
  two.Add({ 1, 0, 0 }, 1.0);
  ar::SurfaceFitOptions o;
  std::string error;
  EXPECT_FALSE(ar::FitSurfaceAutomatic(two.X.data(), two.W.data(), two.Size(), o, true, size, r, error, res));
  EXPECT_NE(error.find("Plane:"), std::string::npos) << error;
  EXPECT_NE(error.find("Cone:"), std::string::npos) << error;
  EXPECT_NE(error.find("Quadric:"), std::string::npos) << error;
  EXPECT_TRUE(std::isnan(res[0]) && std::isnan(res[1]) && std::isnan(res[2]));
}

TEST(SurfaceFit, AutomaticQuadricAboutTheFlowOnAQuarterBowShock)
{
  // A quarter of a sphere's bow shock (Billig's hyperboloid about +x, Mach
  // 3, radius 0.5: vertex at x = -0.6025), y, z >= 0 as a quarter domain
  // between two symmetry planes holds it, out to r = 0.95; points scattered
  // by 0.006 about cells of 0.035. The principal frame stands about 40
  // degrees off the flow, and its paraboloid misses the vertex on the axis
  // (sphereMa3 of the validation matrix: 1.4 cells); the quadric about the
  // flow (GraphAxis) finds it.
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> ur(0.0, 1.0), uphi(0.0, 0.5 * Pi);
  std::normal_distribution<double> noise(0.0, 0.006);
  const double rc = 0.723, cot2 = 8.0, tanMu = std::sqrt(1.0 / 8.0), x0 = -0.6025, size = 0.035;
  auto shockX = [&](double r) { return x0 + rc * cot2 * (std::sqrt(1.0 + (r * tanMu / rc) * (r * tanMu / rc)) - 1.0); };
  Cloud c;
  for (int i = 0; i < 3000; ++i)
  {
    const double r = 0.95 * std::sqrt(ur(rng)), phi = uphi(rng);
    c.Add({ shockX(r) + noise(rng), r * std::cos(phi) + noise(rng), r * std::sin(phi) + noise(rng) }, 1.0 / size);
  }
  auto vertex = [&](const ar::SurfaceFitResult& f) {
    // where the surface crosses the axis near the true vertex
    double best = std::numeric_limits<double>::quiet_NaN(), previous = 0.0;
    for (int k = 0; k <= 4000; ++k)
    {
      const double x = -0.8 + 0.4 * k / 4000.0, p[3] = { x, 0.0, 0.0 };
      const double d = ar::SurfaceDistance(f, p);
      if (k > 0 && (d > 0.0) != (previous > 0.0) &&
        (std::isnan(best) || std::abs(x - x0) < std::abs(best - x0)))
      {
        best = x;
      }
      previous = d;
    }
    return best;
  };
  ar::SurfaceFitOptions o;
  ar::SurfaceFitResult principal, about;
  std::string error;
  double res[4];
  ASSERT_TRUE(ar::FitSurfaceAutomatic(c.X.data(), c.W.data(), c.Size(), o, true, size, principal, error, res))
    << error;
  const double residualPrincipal = res[2];
  o.GraphAxis[0] = 2.9; // a free stream's velocity
  o.GraphAxis[1] = 0.02;
  ASSERT_TRUE(ar::FitSurfaceAutomatic(c.X.data(), c.W.data(), c.Size(), o, true, size, about, error, res)) << error;
  const double vp = vertex(principal), va = vertex(about);
  std::printf("quarter bow shock: principal frame %s, vertex %+.4f off (rms %.4f); about the flow %s, vertex %+.4f "
              "off (rms %.4f)\n",
    ar::SurfaceTemplateName(principal.Template), vp - x0, residualPrincipal, ar::SurfaceTemplateName(about.Template),
    va - x0, res[2]);
  EXPECT_EQ(about.Template, ar::SurfaceTemplate::Quadric);
  EXPECT_LT(res[2], residualPrincipal) << "the quadric about the flow kept for its lower residual";
  EXPECT_LT(std::abs(va - x0), 0.5 * size) << "the vertex within half a cell";
  EXPECT_GT(std::abs(vp - x0), 2.0 * std::abs(va - x0)) << "what the second frame is for";
}

TEST(SurfaceFit, RobustScaleFollowsTheLocalSize)
{
  // A half cone whose mesh grows five-fold along the generators (l from 0.01
  // at s = 1 to 0.05 at s = 3), the medial points scattered by a fifth of
  // their local size, with a thick tail (5 % at a full cell): as a captured
  // conical shock's medial points on a graded mesh. The robust fit, which
  // judges each point against its own size, agrees with the plain fit; a
  // single global scale would reject the coarse part's good points and tilt
  // the cone.
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> us(1.0, 3.0), uphi(0.0, Pi), tail(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 1.0);
  const V apex{ 0.1, 0.2, -0.3 }, z = Unit({ 1.0, 0.2, 0.1 });
  const double theta = 32.0 * Pi / 180.0;
  V e1, e2;
  Perpendiculars(z, e1, e2);
  Cloud c;
  for (int i = 0; i < 4000; ++i)
  {
    const double s = us(rng), phi = uphi(rng);
    const double l = 0.01 + 0.02 * (s - 1.0);
    const double sigma = tail(rng) < 0.05 ? l : 0.2 * l;
    const V radial = Add(Add(V{ 0, 0, 0 }, e1, std::cos(phi)), e2, std::sin(phi));
    const V g = Add(Add(V{ 0, 0, 0 }, z, std::cos(theta)), radial, std::sin(theta));
    const V normal = Add(Add(V{ 0, 0, 0 }, radial, std::cos(theta)), z, -std::sin(theta));
    c.Add(Add(Add(apex, g, s), normal, sigma * noise(rng)), 1.0 / l);
  }
  ar::SurfaceFitOptions o;
  o.Template = ar::SurfaceTemplate::Cone;
  ar::SurfaceFitResult plain, robust;
  std::string error;
  ASSERT_TRUE(ar::FitSurface(c.X.data(), c.W.data(), c.Size(), o, plain, error)) << error;
  std::vector<double> m;
  ASSERT_TRUE(ar::FitSurfaceRobust(c.X.data(), c.W.data(), c.Size(), o, robust, error, 10, &m)) << error;
  // The down-weighted share (multiplier below 0.5) of the fine and the
  // coarse third of the points: alike when the scale follows the size (a
  // global scale down-weights the coarse third's ordinary scatter, ~13 %).
  std::size_t fine = 0, coarse = 0, fineLow = 0, coarseLow = 0;
  for (std::size_t j = 0; j < c.Size(); ++j)
  {
    const double l = 1.0 / c.W[j];
    if (l < 0.01 + 0.02 * (2.0 / 3.0))
    {
      ++fine;
      fineLow += m[j] < 0.5 ? 1 : 0;
    }
    else if (l > 0.01 + 0.02 * (4.0 / 3.0))
    {
      ++coarse;
      coarseLow += m[j] < 0.5 ? 1 : 0;
    }
  }
  const double fineShare = double(fineLow) / fine, coarseShare = double(coarseLow) / coarse;
  std::printf("graded cone: plain half-angle %.3f, robust %.3f (true 32); down-weighted: fine %.3f, coarse %.3f\n",
    plain.HalfAngleDegrees, robust.HalfAngleDegrees, fineShare, coarseShare);
  EXPECT_LT(coarseShare, 0.08);
  EXPECT_LT(std::abs(coarseShare - fineShare), 0.03);
  EXPECT_NEAR(plain.HalfAngleDegrees, 32.0, 0.1);
  EXPECT_NEAR(robust.HalfAngleDegrees, plain.HalfAngleDegrees, 0.1);
  EXPECT_LT(AngleDeg({ robust.AxisDirection[0], robust.AxisDirection[1], robust.AxisDirection[2] }, z), 0.2);
}

TEST(SurfaceFit, AutomaticTemplateOnAOneCellDeepBand)
{
  // A 2-D mesh's medial points: a noisy line in the section, on the front
  // and the back plane (z = +-0.005) only. A cone through the two lines
  // fits them better than the plane (it fits the two levels), but it is not
  // the shock: it is not tried; the quadric and the quartic, extruded along
  // the depth, fit the noise no better than the plane, which is chosen.
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.002);
  Cloud c;
  for (int i = 0; i < 400; ++i)
  {
    const double s = u(rng);
    const double z = (i % 2) ? 0.005 : -0.005;
    c.Add({ s, 0.45 * s + noise(rng), z }, 1.0 / 0.01);
  }
  ar::SurfaceFitOptions o;
  ar::SurfaceFitResult r;
  std::string error;
  double res[4];
  ASSERT_TRUE(ar::FitSurfaceAutomatic(c.X.data(), c.W.data(), c.Size(), o, true, 0.01, r, error, res)) << error;
  std::printf("one cell deep: %s (residuals plane %.5f, cone %.5f, quadric %.5f, quartic %.5f), normal %.4f %.4f %.4f\n",
    ar::SurfaceTemplateName(r.Template), res[0], res[1], res[2], res[3], r.Normal[0], r.Normal[1], r.Normal[2]);
  EXPECT_EQ(r.Template, ar::SurfaceTemplate::Plane);
  EXPECT_TRUE(std::isnan(res[1])) << "the cone is not tried";
  EXPECT_TRUE(std::isfinite(res[2]) && std::isfinite(res[3])) << "the extruded quadric and quartic are";
  EXPECT_GT(res[2], 0.9 * res[0]) << "the noise is not a curve";
  // The line in the section (the depth tilt is not determined by two levels
  // 0.01 apart; EmbeddedRemesh's 2-D mode cuts S at mid-depth).
  EXPECT_LT(AngleDeg({ r.Normal[0], r.Normal[1], 0.0 }, Unit({ -0.45, 1.0, 0.0 })), 0.2);
}

TEST(SurfaceFit, OneCellDeepArcThickerThanTheMesh)
{
  // A piece of a 2-D bow shock: an arc of radius 1.5 over 25 degrees (its
  // sagitta 0.036) on the front and back planes of a mesh 0.01 deep. The
  // points spread less along the depth than across the arc, so a plain
  // principal-direction plane is the front plane (normal along z; the
  // cylinderMa3 validation case's eight clusters all got it, and nothing
  // crossed the mid-depth plane). The plane must contain the depth axis and
  // lie along the arc's chord.
  std::mt19937 rng(37);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Cloud c;
  const double pi = std::acos(-1.0);
  for (int i = 0; i < 300; ++i)
  {
    const double t = (20.0 + 25.0 * u(rng)) * pi / 180.0;
    const double z = (i % 2) ? 0.005 : -0.005;
    c.Add({ -1.5 * std::cos(t), 1.5 * std::sin(t), z }, 1.0 / 0.015);
  }
  ar::SurfaceFitOptions o;
  ar::SurfaceFitResult r;
  std::string error;
  o.ExtrusionAxis = 2; // as FitSurfaceAutomatic sets it on these points
  ASSERT_TRUE(ar::FitSurface(c.X.data(), c.W.data(), c.Size(), o, r, error)) << error;
  EXPECT_EQ(r.Template, ar::SurfaceTemplate::Plane);
  EXPECT_LT(std::abs(r.Normal[2]), 1e-12) << "the plane contains the depth axis";
  // The chord's normal: the arc's mid-angle direction, 32.5 degrees.
  const double mid = 32.5 * pi / 180.0;
  EXPECT_LT(AngleDeg({ std::abs(r.Normal[0]), std::abs(r.Normal[1]), 0.0 }, Unit({ std::cos(mid), std::sin(mid), 0.0 })), 2.0);
  EXPECT_LT(r.RMSResidual, 0.02) << "the sagitta's scale, not the arc's length";
  // Meshed with an edge twice the depth, the plane still has a row of points
  // at mid-depth along the whole arc (the domain's trim keeps the strip
  // between the front and back planes; the two clusters of cylinderMa3 whose
  // grid fell between two columns were trimmed to 2-3 triangles).
  ar::SurfaceMesh mesh;
  ASSERT_TRUE(ar::TessellateSurface(r, c.X.data(), c.Size(), 0.02, 0.02, mesh, error)) << error;
  double lo = 1e9, hi = -1e9;
  std::size_t middle = 0;
  for (std::size_t i = 0; i < mesh.Points.size(); i += 3)
  {
    if (std::abs(mesh.Points[i + 2]) < 1e-9)
    {
      ++middle;
      lo = std::min(lo, mesh.Points[i + 1]);
      hi = std::max(hi, mesh.Points[i + 1]);
    }
  }
  EXPECT_GE(middle, 10u);
  EXPECT_LT(lo, 1.5 * std::sin(20.0 * pi / 180.0)) << "from the arc's lower end";
  EXPECT_GT(hi, 1.5 * std::sin(45.0 * pi / 180.0)) << "to its upper end";
}

// A 2-D bow shock: Billig's (1967) correlation for Mach 3 over a cylinder of
// radius 0.5 (standoff 0.324, vertex radius 2.02, asymptotes at the Mach
// angle), the upper half y in [0, 1.8] (symmetry plane y = 0) on the front
// and back planes of a mesh 0.01 deep, as a band of noise 0.002 (a quarter
// of the cells, 0.008). The shock turns 50 degrees. A parabola through it
// misses the vertex by 1.6 cells (its error is largest at the ends); the
// automatic choice is the quartic, extruded along the depth, and its vertex
// is within a quarter of a cell.
TEST(SurfaceFit, OneCellDeepBowShockVertex)
{
  const double R = 0.5, standoff = 0.324, Rc = 2.02, beta = std::asin(1.0 / 3.0);
  const double t2 = std::tan(beta) * std::tan(beta);
  auto shockX = [&](double y) { return -(R + standoff) + Rc / t2 * (std::sqrt(1.0 + y * y * t2 / (Rc * Rc)) - 1.0); };
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.002);
  Cloud c;
  for (int i = 0; i < 600; ++i)
  {
    const double y = 1.8 * u(rng);
    const double z = (i % 2) ? 0.005 : -0.005;
    c.Add({ shockX(y) + noise(rng), y, z }, 1.0 / 0.008);
  }
  ar::SurfaceFitOptions o;
  ar::SurfaceFitResult r;
  std::string error;
  double res[4];
  ASSERT_TRUE(ar::FitSurfaceAutomatic(c.X.data(), c.W.data(), c.Size(), o, true, 0.008, r, error, res)) << error;
  std::printf("bow shock: %s (residuals plane %.5f, cone %.5f, quadric %.5f, quartic %.5f)\n",
    ar::SurfaceTemplateName(r.Template), res[0], res[1], res[2], res[3]);
  EXPECT_EQ(r.Template, ar::SurfaceTemplate::Quartic);
  EXPECT_TRUE(std::isnan(res[1])) << "the cone is not tried";
  EXPECT_GT(std::abs(r.FrameY[2]), 1.0 - 1e-12) << "the frame's y is the depth axis";
  ASSERT_EQ(r.Coefficients.size(), 15u);
  // Monomials by total degree, then falling power of x: only 1, x, ..., x^4.
  for (int d = 0, k = 0; d <= 4; ++d)
  {
    for (int i = d; i >= 0; --i, ++k)
    {
      if (i != d)
      {
        EXPECT_EQ(r.Coefficients[k], 0.0) << "coefficient " << k << " has a power of y";
      }
    }
  }
  // Where the surface crosses the stagnation line (y = 0, at mid-depth and
  // on the front plane): bisection on the signed distance.
  auto crossing = [&](const ar::SurfaceFitResult& f, double z) {
    double a = -1.2, b = -0.5;
    const double pa[3] = { a, 0.0, z };
    const double sa = ar::SurfaceDistance(f, pa);
    for (int it = 0; it < 60; ++it)
    {
      const double m = 0.5 * (a + b);
      const double pm[3] = { m, 0.0, z };
      ((ar::SurfaceDistance(f, pm) > 0.0) == (sa > 0.0) ? a : b) = m;
    }
    return 0.5 * (a + b);
  };
  const double vertex = shockX(0.0);
  const double x0 = crossing(r, 0.0);
  std::printf("bow shock vertex: fitted %.5f, true %.5f (%+.5f)\n", x0, vertex, x0 - vertex);
  EXPECT_LT(std::abs(x0 - vertex), 0.002) << "within a quarter of a cell";
  EXPECT_NEAR(crossing(r, 0.005), x0, 1e-12) << "extruded: the same on the front plane";
  ar::SurfaceFitResult q;
  o.Template = ar::SurfaceTemplate::Quadric;
  o.ExtrusionAxis = 2;
  ASSERT_TRUE(ar::FitSurface(c.X.data(), c.W.data(), c.Size(), o, q, error)) << error;
  EXPECT_GT(std::abs(crossing(q, 0.0) - vertex), 0.006) << "why not the parabola: it misses the vertex";
  // Meshed, the quartic has a row of points at mid-depth from the vertex to
  // the far end.
  ar::SurfaceMesh mesh;
  ASSERT_TRUE(ar::TessellateSurface(r, c.X.data(), c.Size(), 0.02, 0.02, mesh, error)) << error;
  double lo = 1e9, hi = -1e9;
  for (std::size_t i = 0; i < mesh.Points.size(); i += 3)
  {
    if (std::abs(mesh.Points[i + 2]) < 1e-9)
    {
      lo = std::min(lo, mesh.Points[i + 1]);
      hi = std::max(hi, mesh.Points[i + 1]);
      const double y = mesh.Points[i + 1];
      if (y >= 0.0 && y <= 1.8) // (the mesh reaches beyond the points by the pad)
      {
        EXPECT_NEAR(mesh.Points[i], shockX(y), 0.005);
      }
    }
  }
  EXPECT_LT(lo, 0.02);
  EXPECT_GT(hi, 1.75);
}

// Two families of directions (the two-shocks-meet check of AdaptToShocks):
// two tight families 35 degrees apart are found with their angle and a small
// spread, signs ignored; one family gives close axes; a cone's normals (a
// continuous arc) split into halves at most 4 times their spread apart.
TEST(SurfaceFit, DirectionFamilies)
{
  std::mt19937 rng(5);
  std::normal_distribution<double> jitter(0.0, 0.01);
  auto unit = [](double theta, double phi) {
    return V{ std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta) };
  };
  std::vector<double> d, w;
  auto add = [&](const V& v, double weight, double sign) {
    for (int k = 0; k < 3; ++k)
    {
      d.push_back(sign * v[k] + jitter(rng));
    }
    w.push_back(weight);
  };
  // two families: 300 and 200 directions at 0.3 and 0.3 + 35 degrees from z
  for (int i = 0; i < 500; ++i)
  {
    add(unit((i < 300 ? 0.3 : 35.3) * Pi / 180.0, 0.4), 1.0 + (i % 3), i % 2 ? 1.0 : -1.0);
  }
  ar::DirectionFamilies f;
  ASSERT_TRUE(ar::SplitDirectionFamilies(d.data(), w.data(), w.size(), f));
  EXPECT_NEAR(f.AngleDegrees, 35.0, 0.5);
  EXPECT_LT(f.SpreadDegrees, 1.5);
  EXPECT_NEAR(f.Fraction, 0.4, 0.02);
  // one family
  d.clear();
  w.clear();
  for (int i = 0; i < 500; ++i)
  {
    add(unit(0.5, 1.0), 1.0, i % 2 ? 1.0 : -1.0);
  }
  ASSERT_TRUE(ar::SplitDirectionFamilies(d.data(), w.data(), w.size(), f));
  EXPECT_LT(f.AngleDegrees, 3.0);
  // a cone's normals round its axis over a quarter turn: a continuous family
  d.clear();
  w.clear();
  for (int i = 0; i < 900; ++i)
  {
    add(unit(60.0 * Pi / 180.0, 0.5 * Pi * i / 899.0), 1.0, 1.0);
  }
  ASSERT_TRUE(ar::SplitDirectionFamilies(d.data(), w.data(), w.size(), f));
  EXPECT_GT(f.AngleDegrees, 30.0);
  EXPECT_LT(f.AngleDegrees, 4.2 * f.SpreadDegrees);
  // nothing to split
  const double one[3] = { 1.0, 0.0, 0.0 }, weight = 1.0;
  EXPECT_FALSE(ar::SplitDirectionFamilies(one, &weight, 1, f));
}
