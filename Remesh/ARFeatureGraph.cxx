// SPDX-License-Identifier: BSD-3-Clause
#include "ARFeatureGraph.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <utility>

namespace ar
{
FeatureGraphResult ClusterFeatures(const FeatureGraphInput& in)
{
  const std::size_t n = in.NumberOfPoints;
  FeatureGraphResult out;
  out.Mask.assign(n, 0);
  out.ClusterId.assign(n, -1);
  out.Distance.assign(n, -1);
  out.Medial.assign(n, 0);
  out.LocalSize.assign(n, 0.0);
  if (n == 0)
  {
    return out;
  }

  // ---- Adjacency (CSR) of the undirected, de-duplicated edges.
  std::vector<std::pair<std::int64_t, std::int64_t>> edges;
  edges.reserve(in.NumberOfEdges);
  for (std::size_t e = 0; e < in.NumberOfEdges; ++e)
  {
    std::int64_t a = in.Edges[2 * e], b = in.Edges[2 * e + 1];
    if (a == b || a < 0 || b < 0 || static_cast<std::size_t>(a) >= n || static_cast<std::size_t>(b) >= n)
    {
      continue;
    }
    edges.emplace_back(std::min(a, b), std::max(a, b));
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  std::vector<std::int64_t> offsets(n + 1, 0), adjacent(2 * edges.size());
  for (const auto& e : edges)
  {
    ++offsets[e.first + 1];
    ++offsets[e.second + 1];
  }
  std::partial_sum(offsets.begin(), offsets.end(), offsets.begin());
  {
    std::vector<std::int64_t> fill(offsets.begin(), offsets.end() - 1);
    for (const auto& e : edges)
    {
      adjacent[fill[e.first]++] = e.second;
      adjacent[fill[e.second]++] = e.first;
    }
  }

  // ---- Longest edge at each node.
  for (const auto& e : edges)
  {
    const double* p = in.Points + 3 * e.first;
    const double* q = in.Points + 3 * e.second;
    const double len = std::sqrt(
      (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]));
    out.LocalSize[e.first] = std::max(out.LocalSize[e.first], len);
    out.LocalSize[e.second] = std::max(out.LocalSize[e.second], len);
  }

  // ---- Step 2: dilation by rings (breadth-first levels from the seeds).
  std::vector<std::uint8_t> selected(n, 0);
  std::vector<std::int64_t> front, next;
  for (std::size_t i = 0; i < n; ++i)
  {
    if (in.Seeds[i])
    {
      selected[i] = 1;
      front.push_back(static_cast<std::int64_t>(i));
    }
  }
  for (int ring = 0; ring < in.DilationRings && !front.empty(); ++ring)
  {
    next.clear();
    for (std::int64_t i : front)
    {
      for (std::int64_t k = offsets[i]; k < offsets[i + 1]; ++k)
      {
        const std::int64_t j = adjacent[k];
        if (!selected[j])
        {
          selected[j] = 1;
          next.push_back(j);
        }
      }
    }
    front.swap(next);
  }

  // ---- Step 3: connected clusters of selected nodes.
  std::vector<int> component(n, -1);
  std::vector<std::int64_t> sizes;
  std::vector<std::array<double, 3>> smallest; // lexicographically smallest position
  for (std::size_t s = 0; s < n; ++s)
  {
    if (!selected[s] || component[s] >= 0)
    {
      continue;
    }
    const int id = static_cast<int>(sizes.size());
    std::int64_t count = 0;
    std::array<double, 3> low = { in.Points[3 * s], in.Points[3 * s + 1], in.Points[3 * s + 2] };
    front.assign(1, static_cast<std::int64_t>(s));
    component[s] = id;
    while (!front.empty())
    {
      const std::int64_t i = front.back();
      front.pop_back();
      ++count;
      const std::array<double, 3> x = { in.Points[3 * i], in.Points[3 * i + 1], in.Points[3 * i + 2] };
      low = std::min(low, x);
      for (std::int64_t k = offsets[i]; k < offsets[i + 1]; ++k)
      {
        const std::int64_t j = adjacent[k];
        if (selected[j] && component[j] < 0)
        {
          component[j] = id;
          front.push_back(j);
        }
      }
    }
    sizes.push_back(count);
    smallest.push_back(low);
  }
  std::vector<int> order(sizes.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return sizes[a] != sizes[b] ? sizes[a] > sizes[b] : smallest[a] < smallest[b];
  });
  std::vector<int> newId(sizes.size(), -1);
  for (int rank = 0, kept = 0; rank < static_cast<int>(order.size()); ++rank)
  {
    if (sizes[order[rank]] >= in.MinimumClusterSize)
    {
      newId[order[rank]] = kept++;
      out.ClusterSizes.push_back(sizes[order[rank]]);
    }
  }
  for (std::size_t i = 0; i < n; ++i)
  {
    if (component[i] >= 0 && newId[component[i]] >= 0)
    {
      out.ClusterId[i] = newId[component[i]];
      out.Mask[i] = 1;
    }
  }

  // ---- Step 4: edge distance from the cluster boundary (multi-source BFS).
  front.clear();
  for (std::size_t i = 0; i < n; ++i)
  {
    if (!out.Mask[i])
    {
      continue;
    }
    for (std::int64_t k = offsets[i]; k < offsets[i + 1]; ++k)
    {
      if (!out.Mask[adjacent[k]])
      {
        out.Distance[i] = 0;
        front.push_back(static_cast<std::int64_t>(i));
        break;
      }
    }
  }
  for (int d = 1; !front.empty(); ++d)
  {
    next.clear();
    for (std::int64_t i : front)
    {
      for (std::int64_t k = offsets[i]; k < offsets[i + 1]; ++k)
      {
        const std::int64_t j = adjacent[k];
        if (out.Mask[j] && out.Distance[j] < 0)
        {
          out.Distance[j] = d;
          next.push_back(j);
        }
      }
    }
    front.swap(next);
  }
  // A cluster with no boundary node (it fills the whole graph) measures from
  // nothing: its nodes stay at -1 and none is medial.

  // ---- Step 5: local maxima (>= every selected neighbour).
  for (std::size_t i = 0; i < n; ++i)
  {
    if (!out.Mask[i] || out.Distance[i] < 0)
    {
      continue;
    }
    bool maximum = true;
    for (std::int64_t k = offsets[i]; k < offsets[i + 1] && maximum; ++k)
    {
      const std::int64_t j = adjacent[k];
      maximum = !out.Mask[j] || out.Distance[j] <= out.Distance[i];
    }
    out.Medial[i] = maximum ? 1 : 0;
  }
  return out;
}
}
