// rayunits util: the project's one parallel loop (a pool of threads for the length of a call).
//
// parallel_for(n, threads, fn) calls fn(i) for every i in [0, n) on up to `threads` threads
// (values below 1 count as 1), the calling thread being one of them. Indices are handed out one at a time in increasing
// order (dynamic: long and short jobs balance); with threads == 1 everything runs on the
// caller in index order, which is what work whose result depends on the order needs (e.g. a
// render trace written in tile order). The first exception thrown by fn stops the handout
// (indices already started finish) and is rethrown in the caller once every thread is done.
//
// parallel_workers(n, threads, body) is the same pool for work that keeps per-thread state:
// body(take) runs once per thread and pulls indices with take(i) until it returns false.
#pragma once

#include <cstddef>
#include <functional>

namespace ru::util {

struct ParallelOptions {
  // Polled before each index is handed out: true stops the handout (e.g. util::interrupted).
  std::function<bool()> stop;
  // Called with (finished, n) at most every progress_period seconds, by one worker at a time
  // (never concurrently), after a job finished.
  std::function<void(std::size_t done, std::size_t n)> progress;
  double progress_period = 2.0;
};

// Hands out the next index: false when none is left (or the loop was stopped).
using TakeIndex = std::function<bool(std::size_t& i)>;

void parallel_workers(std::size_t n, int threads, const std::function<void(const TakeIndex& take)>& body,
                      const ParallelOptions& opt = {});

void parallel_for(std::size_t n, int threads, const std::function<void(std::size_t)>& fn,
                  const ParallelOptions& opt = {});

// std::thread::hardware_concurrency(), at least 1.
unsigned hardware_threads();

}  // namespace ru::util
