// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file ARHugePages.h
 * @brief Large arrays backed by 2 MB pages where Linux allows it.
 *
 * Each first touch of a fresh 4 kB page costs a page fault. On the
 * development machine (a virtual machine) a fault costs about 10
 * microseconds, and AdaptToShocks on 5e6 tetrahedra touches about 7 GB of
 * fresh memory: a quarter of its wall time went to faults. Debian's kernel
 * has transparent huge pages in "madvise" mode: a range marked with
 * madvise(MADV_HUGEPAGE) is faulted in 2 MB at a time (one fault instead of
 * 512, and fewer TLB misses afterwards). glibc's malloc does this for the
 * whole process only when the process is started with
 * GLIBC_TUNABLES=glibc.malloc.hugetlb=1; a plugin cannot set that, so the
 * largest arrays are marked here, between their allocation and their first
 * write.
 *
 * The memory stays malloc's (freed as before); the advice only changes how
 * its pages are faulted in, never the values. Ranges under 4 MB, other
 * systems, and a kernel that says no (THP "never") are left as they are.
 */
#ifndef ARHugePages_h
#define ARHugePages_h

#include <cstddef>
#include <vector>

namespace ar
{
/// Marks the whole 2 MB pages inside [p, p + bytes) for transparent huge
/// pages (Linux madvise MADV_HUGEPAGE). Call it before the range is first
/// written: pages already there stay 4 kB. Ignores failures.
void AdviseHugePages(const void* p, std::size_t bytes);

/// v.reserve(n), and the new room marked by AdviseHugePages: for a large
/// array that is then filled by resize, assign, insert or push_back.
template <typename T, typename A>
void ReserveHuge(std::vector<T, A>& v, std::size_t n)
{
  if (n > v.capacity())
  {
    v.reserve(n);
    AdviseHugePages(v.data() + v.size(), (n - v.size()) * sizeof(T));
  }
}

/// v.assign(n, value), its memory marked first (a fresh buffer when v must
/// grow, so that none of it has been touched).
template <typename T, typename A>
void AssignHuge(std::vector<T, A>& v, std::size_t n, const T& value)
{
  if (n > v.capacity())
  {
    std::vector<T, A>().swap(v);
    ReserveHuge(v, n);
  }
  v.assign(n, value);
}

/// v.resize(n) (new elements value-initialized), the new room marked first.
template <typename T, typename A>
void ResizeHuge(std::vector<T, A>& v, std::size_t n)
{
  ReserveHuge(v, n);
  v.resize(n);
}
}

#endif
