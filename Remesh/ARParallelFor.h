// SPDX-License-Identifier: BSD-3-Clause
/**
 * ar::ParallelFor: a loop over [0, n) on std::threads, in contiguous
 * blocks (the core is VTK-free, so not vtkSMPTools). The caller keeps its
 * results independent of the blocks (each index writes its own entries),
 * so that the output does not depend on the number of threads. An exception
 * thrown in a block reaches the caller.
 */
#ifndef ARParallelFor_h
#define ARParallelFor_h

#include <algorithm>
#include <cstddef>
#include <exception>
#include <functional>
#include <thread>
#include <vector>

namespace ar
{
/// Runs fn(begin, end) over [0, n) in contiguous blocks of at least
/// `grain` indices, on at most `threads` threads (0: the hardware's).
inline void ParallelFor(std::size_t n, const std::function<void(std::size_t, std::size_t)>& fn,
  std::size_t threads = 0, std::size_t grain = 10000)
{
  const std::size_t hardware = std::max<std::size_t>(1, std::thread::hardware_concurrency());
  threads = std::max<std::size_t>(
    1, std::min<std::size_t>(threads == 0 ? hardware : threads, n / std::max<std::size_t>(1, grain)));
  if (threads <= 1)
  {
    fn(0, n);
    return;
  }
  // An exception in a block (std::bad_alloc, say) is rethrown here, on the
  // caller's thread, after every block has ended: one escaping a std::thread
  // would end the process.
  std::vector<std::exception_ptr> failed(threads);
  auto run = [&](std::size_t t, std::size_t first, std::size_t last) {
    try
    {
      fn(first, last);
    }
    catch (...)
    {
      failed[t] = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  const std::size_t block = (n + threads - 1) / threads;
  for (std::size_t t = 1; t < threads; ++t)
  {
    pool.emplace_back(run, t, std::min(n, t * block), std::min(n, (t + 1) * block));
  }
  run(0, 0, std::min(n, block));
  for (std::thread& th : pool)
  {
    th.join();
  }
  for (const std::exception_ptr& e : failed)
  {
    if (e)
    {
      std::rethrow_exception(e);
    }
  }
}
}

#endif
