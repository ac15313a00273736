// Unit tests of ar::ClusterFeatures on lattice graphs whose answers are known
// exactly: slabs of odd and even thickness, dilation, two clusters, minimum size.
#include "ARFeatureGraph.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <set>

namespace
{
/// An n x n x n lattice of unit spacing with its axis-aligned edges, and
/// seeds where `seed(i, j, k)` is true.
struct Lattice
{
  int N;
  std::vector<double> X;
  std::vector<std::uint8_t> Seeds;
  std::vector<std::int64_t> Edges;

  Lattice(int n, const std::function<bool(int, int, int)>& seed)
    : N(n)
  {
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
        {
          X.insert(X.end(), { double(i), double(j), double(k) });
          Seeds.push_back(seed(i, j, k) ? 1 : 0);
          if (i + 1 < n)
            Edges.insert(Edges.end(), { Id(i, j, k), Id(i + 1, j, k) });
          if (j + 1 < n)
            Edges.insert(Edges.end(), { Id(i, j, k), Id(i, j + 1, k) });
          if (k + 1 < n)
            Edges.insert(Edges.end(), { Id(i, j, k), Id(i, j, k + 1) });
        }
  }
  std::int64_t Id(int i, int j, int k) const { return i + N * (j + N * static_cast<std::int64_t>(k)); }

  ar::FeatureGraphResult Run(int rings, int minimum = 1) const
  {
    ar::FeatureGraphInput in;
    in.Points = X.data();
    in.NumberOfPoints = Seeds.size();
    in.Seeds = Seeds.data();
    in.Edges = Edges.data();
    in.NumberOfEdges = Edges.size() / 2;
    in.DilationRings = rings;
    in.MinimumClusterSize = minimum;
    return ar::ClusterFeatures(in);
  }
};
}

TEST(FeatureGraph, OddSlabHasItsMidPlaneAsMedialLayer)
{
  // Seeds: 5 layers x = 4..8 in an 13^3 lattice. Distances 0 1 2 1 0.
  Lattice lat(13, [](int i, int, int) { return i >= 4 && i <= 8; });
  const auto r = lat.Run(0);
  ASSERT_EQ(r.ClusterSizes.size(), 1u);
  EXPECT_EQ(r.ClusterSizes[0], 5 * 13 * 13);
  for (int k = 0; k < 13; ++k)
    for (int j = 0; j < 13; ++j)
      for (int i = 0; i < 13; ++i)
      {
        const auto id = lat.Id(i, j, k);
        const int expected = (i >= 4 && i <= 8) ? std::min(i - 4, 8 - i) : -1;
        ASSERT_EQ(r.Distance[id], expected) << i << " " << j << " " << k;
        ASSERT_EQ(r.Medial[id], i == 6 ? 1 : 0) << i << " " << j << " " << k;
        ASSERT_EQ(r.ClusterId[id], (i >= 4 && i <= 8) ? 0 : -1);
      }
  EXPECT_DOUBLE_EQ(r.LocalSize[lat.Id(6, 6, 6)], 1.0);
}

TEST(FeatureGraph, EvenSlabKeepsBothMiddleLayers)
{
  // 4 layers x = 3..6: distances 0 1 1 0; the plateau x = 4, 5 is medial and
  // its mean is the mid-plane x = 4.5 exactly.
  Lattice lat(11, [](int i, int, int) { return i >= 3 && i <= 6; });
  const auto r = lat.Run(0);
  double sum = 0;
  int count = 0;
  for (std::size_t p = 0; p < r.Medial.size(); ++p)
  {
    if (r.Medial[p])
    {
      sum += lat.X[3 * p];
      ++count;
      EXPECT_TRUE(lat.X[3 * p] == 4.0 || lat.X[3 * p] == 5.0);
    }
  }
  EXPECT_EQ(count, 2 * 11 * 11);
  EXPECT_DOUBLE_EQ(sum / count, 4.5);
}

TEST(FeatureGraph, DilationAddsRings)
{
  Lattice lat(11, [](int i, int, int) { return i == 5; });
  const auto r0 = lat.Run(0);
  const auto r2 = lat.Run(2);
  EXPECT_EQ(r0.ClusterSizes[0], 11 * 11);
  EXPECT_EQ(r2.ClusterSizes[0], 5 * 11 * 11); // x = 3..7
  // One layer thick: every node is on the boundary and medial.
  for (std::size_t p = 0; p < r0.Medial.size(); ++p)
  {
    EXPECT_EQ(r0.Medial[p], lat.Seeds[p]);
  }
}

TEST(FeatureGraph, TwoShocksTwoClustersOrderedBySizeAndMinimumDropsNoise)
{
  // A thick slab x = 1..3, a thinner one x = 8..9, and a lone seed (noise).
  Lattice lat(12, [](int i, int j, int k) {
    return (i >= 1 && i <= 3) || (i >= 8 && i <= 9) || (i == 6 && j == 6 && k == 6);
  });
  const auto all = lat.Run(0, 1);
  ASSERT_EQ(all.ClusterSizes.size(), 3u);
  EXPECT_EQ(all.ClusterSizes[0], 3 * 144);
  EXPECT_EQ(all.ClusterSizes[1], 2 * 144);
  EXPECT_EQ(all.ClusterSizes[2], 1);
  EXPECT_EQ(all.ClusterId[lat.Id(2, 0, 0)], 0);
  EXPECT_EQ(all.ClusterId[lat.Id(9, 5, 5)], 1);
  const auto kept = lat.Run(0, 10);
  ASSERT_EQ(kept.ClusterSizes.size(), 2u);
  EXPECT_EQ(kept.ClusterId[lat.Id(6, 6, 6)], -1);
  EXPECT_EQ(kept.Mask[lat.Id(6, 6, 6)], 0);
}

TEST(FeatureGraph, EqualSizesAreOrderedByPosition)
{
  Lattice lat(10, [](int i, int, int) { return i == 7 || i == 2; });
  const auto r = lat.Run(0);
  ASSERT_EQ(r.ClusterSizes.size(), 2u);
  EXPECT_EQ(r.ClusterId[lat.Id(2, 0, 0)], 0); // smaller x first
  EXPECT_EQ(r.ClusterId[lat.Id(7, 0, 0)], 1);
}

TEST(FeatureGraph, NoSeedNoCluster)
{
  Lattice lat(5, [](int, int, int) { return false; });
  const auto r = lat.Run(1);
  EXPECT_TRUE(r.ClusterSizes.empty());
  for (auto m : r.Mask)
  {
    EXPECT_EQ(m, 0);
  }
}
