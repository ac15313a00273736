// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file ARUnionFind.h
 * @brief Disjoint sets over 0..n-1 with path halving; the smaller id becomes
 *        the root, so the partition's representatives do not depend on the
 *        order of the unions. Internal to Remesh/.
 */
#ifndef ARUnionFind_h
#define ARUnionFind_h

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

namespace ar
{
struct UnionFind
{
  std::vector<std::int64_t> Parent;

  explicit UnionFind(std::size_t n)
    : Parent(n)
  {
    std::iota(this->Parent.begin(), this->Parent.end(), std::int64_t(0));
  }

  std::int64_t Find(std::int64_t i)
  {
    while (this->Parent[i] != i)
    {
      this->Parent[i] = this->Parent[this->Parent[i]];
      i = this->Parent[i];
    }
    return i;
  }

  void Union(std::int64_t a, std::int64_t b)
  {
    a = this->Find(a);
    b = this->Find(b);
    if (a != b)
    {
      this->Parent[std::max(a, b)] = std::min(a, b);
    }
  }
};
}

#endif
