// SPDX-License-Identifier: BSD-3-Clause
#include "ARMeshSize.h"

#include <algorithm>
#include <cmath>

namespace ar
{
namespace
{
double Distance(const double* p, const double* q, int dimension)
{
  double s = 0.0;
  for (int k = 0; k < dimension; ++k)
  {
    s += (p[k] - q[k]) * (p[k] - q[k]);
  }
  return std::sqrt(s);
}
}

void AccumulateLongestEdges(CellShape shape, const double* points, const std::int64_t* cells,
  std::size_t nCells, std::vector<double>& lv)
{
  const int nodes = NumberOfNodes(shape), edges = NumberOfEdges(shape);
  for (std::size_t c = 0; c < nCells; ++c)
  {
    const std::int64_t* v = cells + static_cast<std::size_t>(nodes) * c;
    for (int e = 0; e < edges; ++e)
    {
      int a, b;
      CellEdge(shape, e, a, b);
      const double l = Distance(&points[3 * v[a]], &points[3 * v[b]], 3);
      lv[v[a]] = std::max(lv[v[a]], l);
      lv[v[b]] = std::max(lv[v[b]], l);
    }
  }
}

std::vector<double> LongestEdgeAtNodes(const double* points, std::size_t nPoints,
  const std::int64_t* tetrahedra, std::size_t nTetrahedra)
{
  std::vector<double> lv(nPoints, 0.0);
  AccumulateLongestEdges(CellShape::Tetrahedron, points, tetrahedra, nTetrahedra, lv);
  return lv;
}

std::vector<double> LongestPolygonEdgeAtNodes(const double* points, int dimension, std::size_t nPoints,
  const std::int64_t* offsets, const std::int64_t* connectivity, std::size_t nCells)
{
  std::vector<double> lv(nPoints, 0.0);
  for (std::size_t c = 0; c < nCells; ++c)
  {
    const std::int64_t n = offsets[c + 1] - offsets[c];
    const std::int64_t* v = connectivity + offsets[c];
    for (std::int64_t j = 0; j < n; ++j)
    {
      const std::int64_t a = v[j], b = v[(j + 1) % n];
      const double l = Distance(&points[dimension * a], &points[dimension * b], dimension);
      lv[a] = std::max(lv[a], l);
      lv[b] = std::max(lv[b], l);
    }
  }
  return lv;
}

double Median(std::vector<double> values)
{
  if (values.empty())
  {
    return 0.0;
  }
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

double MedianAtNodes(const std::vector<double>& lv, const std::int64_t* nodes, std::size_t n)
{
  std::vector<std::int64_t> ids(nodes, nodes + n);
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  std::vector<double> values;
  values.reserve(ids.size());
  for (const std::int64_t i : ids)
  {
    if (lv[i] > 0.0)
    {
      values.push_back(lv[i]);
    }
  }
  return Median(std::move(values));
}
}
