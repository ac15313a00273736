// SPDX-License-Identifier: BSD-3-Clause
#include "ARTetGen.h"
#include "ARCGALTypes.h"

#include "ARHugePages.h"
#include "ARTetGeometry.h"

#include <CGAL/Polygon_mesh_processing/self_intersections.h>

#include <tetgen.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <array>
#include <cmath>
#include <csignal>
#include <cstring>
#include <cstdio>
#include <map>
#include <mutex>
#include <sstream>
#include <utility>
#include <vector>

namespace ar
{
namespace
{
bool ValidateSurface(const double* xyz, std::size_t nPoints, const std::int64_t* tri,
  std::size_t nTriangles, std::string& error)
{
  if (nPoints < 4 || nTriangles < 4)
  {
    error = "a closed surface needs at least 4 points and 4 triangles (got " +
      std::to_string(nPoints) + " points, " + std::to_string(nTriangles) + " triangles).";
    return false;
  }
  for (std::size_t i = 0; i < 3 * nPoints; ++i)
  {
    if (!std::isfinite(xyz[i]))
    {
      error = "point " + std::to_string(i / 3) + " has a non-finite coordinate.";
      return false;
    }
  }
  std::map<std::pair<std::int64_t, std::int64_t>, int> edgeUse;
  for (std::size_t t = 0; t < nTriangles; ++t)
  {
    const std::int64_t* v = tri + 3 * t;
    for (int k = 0; k < 3; ++k)
    {
      if (v[k] < 0 || static_cast<std::size_t>(v[k]) >= nPoints)
      {
        error = "triangle " + std::to_string(t) + " refers to point " + std::to_string(v[k]) +
          ", which does not exist.";
        return false;
      }
    }
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2])
    {
      error = "triangle " + std::to_string(t) + " repeats a vertex.";
      return false;
    }
    const double* a = xyz + 3 * v[0];
    const double* b = xyz + 3 * v[1];
    const double* c = xyz + 3 * v[2];
    const double u[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
    const double w[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
    const double n[3] = { u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
      u[0] * w[1] - u[1] * w[0] };
    if (n[0] == 0.0 && n[1] == 0.0 && n[2] == 0.0)
    {
      error = "triangle " + std::to_string(t) + " has zero area.";
      return false;
    }
    for (int k = 0; k < 3; ++k)
    {
      std::int64_t p = v[k], q = v[(k + 1) % 3];
      ++edgeUse[std::make_pair(std::min(p, q), std::max(p, q))];
    }
  }
  for (const auto& e : edgeUse)
  {
    if (e.second != 2)
    {
      error = "the surface is not closed and manifold: edge (" + std::to_string(e.first.first) +
        ", " + std::to_string(e.first.second) + ") belongs to " + std::to_string(e.second) +
        " triangle(s) instead of 2.";
      return false;
    }
  }

  // Orientation and self-intersection, with CGAL (exact predicates): TetGen
  // would throw, or corrupt its heap, on such input.
  std::vector<cgal::Point> points;
  points.reserve(nPoints);
  for (std::size_t i = 0; i < nPoints; ++i)
  {
    points.emplace_back(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
  }
  cgal::Soup faces(nTriangles);
  for (std::size_t t = 0; t < nTriangles; ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      faces[t][k] = static_cast<std::size_t>(tri[3 * t + k]);
    }
  }
  cgal::Mesh mesh;
  if (!cgal::SoupToMesh(points, faces, mesh))
  {
    error = "the surface triangles are not consistently oriented (or a vertex is non-manifold).";
    return false;
  }
  if (cgal::PMP::does_self_intersect(mesh))
  {
    error = "the surface intersects itself.";
    return false;
  }
  return true;
}
}

std::string TetGenSwitches(const TetGenOptions& options)
{
  std::ostringstream s;
  s << "p";
  if (options.MaxRadiusEdgeRatio > 0.0)
  {
    s << "q" << options.MaxRadiusEdgeRatio;
    if (options.MinDihedralAngle > 0.0)
    {
      s << "/" << options.MinDihedralAngle;
    }
  }
  if (options.MaxVolume > 0.0)
  {
    s << "a" << options.MaxVolume;
  }
  if (options.PreserveSurface)
  {
    s << "Y";
  }
  if (options.OptimizationLevel > 0)
  {
    s << "O" << options.OptimizationLevel << "/7";
  }
  if (options.OptimizeMaxDihedral > 0.0)
  {
    s << "o/" << options.OptimizeMaxDihedral;
  }
  s << "Q";
  return s.str();
}

namespace
{
/// Runs TetGen with `switches`; on failure `error` says why.
bool RunTetGen(tetgenio& in, tetgenio& result, const std::string& switches, std::string& error)
{
  std::vector<char> sw(switches.begin(), switches.end());
  sw.push_back('\0');
  try
  {
    tetrahedralize(sw.data(), &in, &result);
  }
  catch (int code)
  {
    // terminatetetgen() codes: 1 out of memory, 2 internal error, 3 self-intersection,
    // 4 small feature, 5 close facets, 10 bad input.
    error = "TetGen failed (code " + std::to_string(code) + ", switches '" + switches + "')";
    switch (code)
    {
      case 3:
        error += ": the surface intersects itself.";
        break;
      case 4:
      case 5:
        error += ": the surface has features too small or facets too close for the tolerance.";
        break;
      case 1:
        error += ": out of memory.";
        break;
      default:
        error += ".";
    }
    return false;
  }
  catch (...)
  {
    error = "TetGen failed with an unexpected exception (switches '" + switches + "').";
    return false;
  }
  if (result.numberoftetrahedra <= 0 || result.numberofcorners != 4)
  {
    error = "TetGen produced no linear tetrahedra (switches '" + switches + "').";
    return false;
  }
  return true;
}

/// TetGen's tetrahedra as a TetMesh, each positively oriented.
void CopyTetrahedra(const tetgenio& result, TetMesh& out)
{
  out.Points.assign(result.pointlist, result.pointlist + 3 * result.numberofpoints);
  out.Tetrahedra.resize(4 * static_cast<std::size_t>(result.numberoftetrahedra));
  for (std::size_t t = 0; t < static_cast<std::size_t>(result.numberoftetrahedra); ++t)
  {
    std::int64_t* v = &out.Tetrahedra[4 * t];
    for (int k = 0; k < 4; ++k)
    {
      v[k] = result.tetrahedronlist[4 * t + k] - result.firstnumber;
    }
    const double* p[4] = { &out.Points[3 * v[0]], &out.Points[3 * v[1]], &out.Points[3 * v[2]],
      &out.Points[3 * v[3]] };
    if (TetSignedVolume(p[0], p[1], p[2], p[3]) < 0.0)
    {
      std::swap(v[1], v[2]);
    }
  }
}

void AddTriangleFacets(tetgenio& in, const std::int64_t* triangles, std::size_t nTriangles,
  const int* markers)
{
  in.numberoffacets = static_cast<int>(nTriangles);
  in.facetlist = new tetgenio::facet[nTriangles];
  if (markers)
  {
    in.facetmarkerlist = new int[nTriangles];
  }
  for (std::size_t t = 0; t < nTriangles; ++t)
  {
    tetgenio::facet& f = in.facetlist[t];
    tetgenio::init(&f);
    f.numberofpolygons = 1;
    f.polygonlist = new tetgenio::polygon[1];
    tetgenio::init(&f.polygonlist[0]);
    f.polygonlist[0].numberofvertices = 3;
    f.polygonlist[0].vertexlist = new int[3];
    for (int k = 0; k < 3; ++k)
    {
      f.polygonlist[0].vertexlist[k] = static_cast<int>(triangles[3 * t + k]);
    }
    if (markers)
    {
      in.facetmarkerlist[t] = markers[t];
    }
  }
}
}

namespace
{
bool MeshComplexHere(const PiecewiseLinearComplex& plc, const TetGenOptions& options,
  TetGenResult& out, std::string& error)
{
  out = TetGenResult();
  const std::size_t nPoints = plc.Points.size() / 3;
  const std::size_t nTriangles = plc.Triangles.size() / 3;
  if (nPoints < 4 || nTriangles < 4)
  {
    error = "the complex has " + std::to_string(nPoints) + " points and " +
      std::to_string(nTriangles) + " triangles; a closed shell needs at least 4 of each.";
    return false;
  }
  for (double v : plc.Points)
  {
    if (!std::isfinite(v))
    {
      error = "the complex has a non-finite coordinate.";
      return false;
    }
  }
  for (std::int64_t id : plc.Triangles)
  {
    if (id < 0 || static_cast<std::size_t>(id) >= nPoints)
    {
      error = "a triangle of the complex refers to a point that does not exist.";
      return false;
    }
  }
  if (!plc.TriangleMarkers.empty() && plc.TriangleMarkers.size() != nTriangles)
  {
    error = "the complex has " + std::to_string(plc.TriangleMarkers.size()) + " markers for " +
      std::to_string(nTriangles) + " triangles.";
    return false;
  }
  const bool sized = !plc.PointSizes.empty();
  if (sized && plc.PointSizes.size() != nPoints)
  {
    error = "the complex has " + std::to_string(plc.PointSizes.size()) + " point sizes for " +
      std::to_string(nPoints) + " points.";
    return false;
  }
  for (double h : plc.PointSizes)
  {
    if (!(h > 0.0) || !std::isfinite(h))
    {
      error = "a point size of the complex is not a positive number.";
      return false;
    }
  }

  tetgenio in, result;
  in.firstnumber = 0;
  in.numberofpoints = static_cast<int>(nPoints);
  in.pointlist = new REAL[3 * nPoints];
  std::copy(plc.Points.begin(), plc.Points.end(), in.pointlist);
  if (sized)
  {
    in.numberofpointmtrs = 1;
    in.pointmtrlist = new REAL[nPoints];
    std::copy(plc.PointSizes.begin(), plc.PointSizes.end(), in.pointmtrlist);
  }
  std::vector<int> markers(plc.TriangleMarkers.begin(), plc.TriangleMarkers.end());
  if (markers.empty())
  {
    markers.assign(nTriangles, 1);
  }
  AddTriangleFacets(in, plc.Triangles.data(), nTriangles, markers.data());
  const std::size_t nHoles = plc.Holes.size() / 3;
  if (nHoles > 0)
  {
    in.numberofholes = static_cast<int>(nHoles);
    in.holelist = new REAL[3 * nHoles];
    std::copy(plc.Holes.begin(), plc.Holes.begin() + 3 * nHoles, in.holelist);
  }
  std::string switches = TetGenSwitches(options);
  if (sized)
  {
    switches.insert(switches.size() - 1, "m"); // before the final Q
  }
  {
    // Points on no triangle (free points to insert): TetGen drops those
    // outside the region and would renumber the points after them; -J keeps
    // every input point at its index (an unused one is in no tetrahedron).
    std::vector<char> onTriangle(nPoints, 0);
    for (std::int64_t v : plc.Triangles)
    {
      onTriangle[v] = 1;
    }
    if (std::find(onTriangle.begin(), onTriangle.end(), 0) != onTriangle.end())
    {
      switches.insert(switches.size() - 1, "J");
    }
  }
  if (!RunTetGen(in, result, switches, error))
  {
    return false;
  }
  CopyTetrahedra(result, out.Mesh);
  out.Faces.resize(3 * static_cast<std::size_t>(result.numberoftrifaces));
  out.FaceMarkers.assign(static_cast<std::size_t>(result.numberoftrifaces), 0);
  for (std::size_t f = 0; f < static_cast<std::size_t>(result.numberoftrifaces); ++f)
  {
    for (int k = 0; k < 3; ++k)
    {
      out.Faces[3 * f + k] = result.trifacelist[3 * f + k] - result.firstnumber;
    }
    if (result.trifacemarkerlist)
    {
      out.FaceMarkers[f] = result.trifacemarkerlist[f];
    }
  }
  return true;
}

// ---- Running TetGen in a child process: TetGen can corrupt its heap and
// crash while cleaning up after an error (seen with two facets 1e-11 apart:
// a segfault in tetgenmesh::freememory after terminatetetgen), which would
// take ParaView down with it. The child sends the result through a pipe.
/// Writes all `bytes` to `fd` (a pipe); false if the reader went away.
bool WriteAll(int fd, const void* data, std::size_t bytes)
{
  const char* p = static_cast<const char*>(data);
  while (bytes > 0)
  {
    const ssize_t w = write(fd, p, bytes);
    if (w <= 0)
    {
      return false;
    }
    p += w;
    bytes -= static_cast<std::size_t>(w);
  }
  return true;
}

/// Reads exactly `bytes` from `fd`; false at an early end of the stream.
bool ReadAll(int fd, void* data, std::size_t bytes)
{
  char* p = static_cast<char*>(data);
  while (bytes > 0)
  {
    const ssize_t r = read(fd, p, bytes);
    if (r <= 0)
    {
      return false;
    }
    p += r;
    bytes -= static_cast<std::size_t>(r);
  }
  return true;
}

/// An array on the pipe: its length, then its values, straight from the
/// array (no staging buffer: the result is hundreds of MB at 5e6).
template <typename V>
bool Put(int fd, const V& v)
{
  const std::uint64_t n = v.size();
  return WriteAll(fd, &n, sizeof(n)) && WriteAll(fd, v.data(), n * sizeof(typename V::value_type));
}

/// Reads an array Put wrote straight into `v`, allocated once at its size.
template <typename T>
bool Get(int fd, std::vector<T>& v)
{
  std::uint64_t n = 0;
  if (!ReadAll(fd, &n, sizeof(n)) || n > (std::uint64_t(1) << 40) / sizeof(T))
  {
    return false;
  }
  ResizeHuge(v, static_cast<std::size_t>(n));
  return ReadAll(fd, v.data(), static_cast<std::size_t>(n) * sizeof(T));
}
}

bool TetGenMeshComplex(const PiecewiseLinearComplex& plc, const TetGenOptions& options,
  TetGenResult& out, std::string& error)
{
  out = TetGenResult();
  // Several threads may mesh at once (ARTetGenPieces.h): a child must not
  // inherit another child's pipe end, which would hold that pipe open (its
  // reader would wait for both children), so the pipe, the fork and the
  // closing of the parent's write end are one step; and TetGen run here
  // (no pipe or no fork) is run by one thread at a time (its globals).
  static std::mutex forking, here;
  auto runHere = [&]() {
    std::lock_guard<std::mutex> lock(here);
    return MeshComplexHere(plc, options, out, error);
  };
  forking.lock();
  int fds[2];
  if (pipe(fds) != 0)
  {
    forking.unlock();
    return runHere(); // no pipe: run here
  }
  std::fflush(nullptr);
  const pid_t pid = fork();
  if (pid < 0)
  {
    close(fds[0]);
    close(fds[1]);
    forking.unlock();
    return runHere();
  }
  if (pid == 0)
  {
    close(fds[0]);
    // A crash here is reported by the parent; the host's handlers (ParaView
    // prints a stack trace) have nothing to add.
    for (int sig : { SIGSEGV, SIGBUS, SIGABRT, SIGFPE, SIGILL })
    {
      std::signal(sig, SIG_DFL);
    }
    TetGenResult result;
    std::string message;
    const bool ok = MeshComplexHere(plc, options, result, message);
    const char status = ok ? 1 : 0;
    const bool sent = WriteAll(fds[1], &status, 1) && Put(fds[1], message) && Put(fds[1], result.Mesh.Points) &&
      Put(fds[1], result.Mesh.Tetrahedra) && Put(fds[1], result.Faces) && Put(fds[1], result.FaceMarkers);
    close(fds[1]);
    _exit(sent ? 0 : 2);
  }
  close(fds[1]);
  forking.unlock();
  char status = 0;
  std::vector<char> message;
  const bool received = ReadAll(fds[0], &status, 1) && Get(fds[0], message) && Get(fds[0], out.Mesh.Points) &&
    Get(fds[0], out.Mesh.Tetrahedra) && Get(fds[0], out.Faces) && Get(fds[0], out.FaceMarkers);
  if (!received)
  {
    // The child's writes must not end in SIGPIPE (reported as a crash):
    // read what is left.
    char chunk[1 << 16];
    while (read(fds[0], chunk, sizeof(chunk)) > 0)
    {
    }
  }
  close(fds[0]);
  int exitStatus = 0;
  waitpid(pid, &exitStatus, 0);
  if (WIFSIGNALED(exitStatus))
  {
    error = "TetGen crashed (signal " + std::to_string(WTERMSIG(exitStatus)) +
      ") on this input; the surfaces are probably too close to each other or to the kept mesh.";
    out = TetGenResult();
    return false;
  }
  if (!received)
  {
    error = "TetGen's process ended without a result (exit status " + std::to_string(exitStatus) + ").";
    out = TetGenResult();
    return false;
  }
  if (!status)
  {
    error.assign(message.begin(), message.end());
    out = TetGenResult();
    return false;
  }
  return true;
}

bool TetGenTetrahedralizeSurface(const double* xyz, std::size_t nPoints,
  const std::int64_t* triangles, std::size_t nTriangles, const TetGenOptions& options,
  TetMesh& out, std::string& error)
{
  out = TetMesh();
  if (!ValidateSurface(xyz, nPoints, triangles, nTriangles, error))
  {
    return false;
  }

  // The same (crash-isolated) path as the cavity refill.
  PiecewiseLinearComplex plc;
  plc.Points.assign(xyz, xyz + 3 * nPoints);
  plc.Triangles.assign(triangles, triangles + 3 * nTriangles);
  TetGenResult result;
  if (!TetGenMeshComplex(plc, options, result, error))
  {
    return false;
  }
  out = std::move(result.Mesh);
  return true;
}

bool WriteTetGenFiles(const PiecewiseLinearComplex& plc, const std::string& prefix, std::string& error)
{
  const std::size_t nPoints = plc.Points.size() / 3;
  const std::size_t nTriangles = plc.Triangles.size() / 3;
  auto open = [&](const char* extension, std::ofstream& file) {
    file.open(prefix + extension);
    file.precision(17);
    if (!file)
    {
      error = "cannot write " + prefix + extension + ".";
    }
    return static_cast<bool>(file);
  };
  std::ofstream node, smesh, mtr;
  if (!open(".node", node) || !open(".smesh", smesh))
  {
    return false;
  }
  node << nPoints << " 3 0 0\n";
  for (std::size_t i = 0; i < nPoints; ++i)
  {
    node << i << ' ' << plc.Points[3 * i] << ' ' << plc.Points[3 * i + 1] << ' ' << plc.Points[3 * i + 2] << '\n';
  }
  // Points are in the .node file; facets carry their markers.
  smesh << "0 3 0 0\n" << nTriangles << " 1\n";
  for (std::size_t t = 0; t < nTriangles; ++t)
  {
    smesh << "3 " << plc.Triangles[3 * t] << ' ' << plc.Triangles[3 * t + 1] << ' ' << plc.Triangles[3 * t + 2]
          << ' ' << (plc.TriangleMarkers.empty() ? 1 : plc.TriangleMarkers[t]) << '\n';
  }
  smesh << plc.Holes.size() / 3 << '\n';
  for (std::size_t h = 0; h < plc.Holes.size() / 3; ++h)
  {
    smesh << h << ' ' << plc.Holes[3 * h] << ' ' << plc.Holes[3 * h + 1] << ' ' << plc.Holes[3 * h + 2] << '\n';
  }
  smesh << "0\n";
  if (!plc.PointSizes.empty())
  {
    if (!open(".mtr", mtr))
    {
      return false;
    }
    mtr << plc.PointSizes.size() << " 1\n";
    for (double s : plc.PointSizes)
    {
      mtr << s << '\n';
    }
  }
  if (!node || !smesh || (!plc.PointSizes.empty() && !mtr))
  {
    error = "writing the TetGen files " + prefix + ".* failed.";
    return false;
  }
  return true;
}
}
