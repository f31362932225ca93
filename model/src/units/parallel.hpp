// Private helper of the units studies: a tiny dynamic parallel-for over [0, n).
#pragma once

#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

namespace ru::units::detail {

// Calls fn(i) for every i in [0, n) from up to `threads` threads (the caller is one of them);
// indices are handed out one at a time, so long and short jobs balance.
template <class Fn>
void parallel_for(size_t n, int threads, Fn fn) {
  std::atomic<size_t> next{0};
  auto worker = [&] {
    for (size_t i; (i = next.fetch_add(1)) < n;) fn(i);
  };
  std::vector<std::thread> pool;
  const int t = std::max(1, std::min<int>(threads, static_cast<int>(n)));
  for (int i = 1; i < t; ++i) pool.emplace_back(worker);
  worker();
  for (auto& th : pool) th.join();
}

}  // namespace ru::units::detail
