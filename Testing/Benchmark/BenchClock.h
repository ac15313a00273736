// SPDX-License-Identifier: BSD-3-Clause
//
// BenchClock.h: the wall clock and peak memory the benchmarks print.
#ifndef BenchClock_h
#define BenchClock_h

#include <sys/resource.h>

#include <chrono>

namespace artest
{
/// Seconds on the steady clock.
inline double Now()
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// This process's peak resident memory so far, MB.
inline double PeakRSSMB()
{
  rusage ru;
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_maxrss / 1024.0;
}
}

#endif
