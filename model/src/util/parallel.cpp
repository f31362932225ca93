// rayunits util: the parallel loop (see rayunits/util/parallel.hpp).
#include "rayunits/util/parallel.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace ru::util {

unsigned hardware_threads() { return std::max(1u, std::thread::hardware_concurrency()); }

void parallel_workers(std::size_t n, int threads, const std::function<void(const TakeIndex& take)>& body,
                      const ParallelOptions& opt) {
  if (n == 0) return;
  using clock = std::chrono::steady_clock;
  std::atomic<std::size_t> next{0}, done{0};
  std::atomic<bool> failed{false};
  std::exception_ptr first_error;
  std::mutex error_mu, progress_mu;
  clock::time_point last_progress = clock::now();

  auto worker = [&] {
    bool holding = false;  // this thread took an index that has not been counted as done
    auto finished_one = [&] {
      if (!holding) return;
      holding = false;
      const std::size_t d = done.fetch_add(1) + 1;
      if (!opt.progress) return;
      std::unique_lock<std::mutex> lock(progress_mu, std::try_to_lock);
      if (!lock.owns_lock()) return;
      const auto now = clock::now();
      if (std::chrono::duration<double>(now - last_progress).count() < opt.progress_period) return;
      last_progress = now;
      opt.progress(d, n);
    };
    const TakeIndex take = [&](std::size_t& i) {
      finished_one();
      if (failed.load() || (opt.stop && opt.stop())) return false;
      i = next.fetch_add(1);
      if (i >= n) return false;
      holding = true;
      return true;
    };
    try {
      body(take);
      finished_one();
    } catch (...) {
      std::lock_guard<std::mutex> lock(error_mu);
      if (!first_error) first_error = std::current_exception();
      failed.store(true);
    }
  };

  const unsigned nt =
      static_cast<unsigned>(std::min<std::size_t>(static_cast<std::size_t>(std::max(1, threads)), n));
  std::vector<std::thread> pool;
  pool.reserve(nt - 1);
  try {
    for (unsigned t = 1; t < nt; ++t) pool.emplace_back(worker);
  } catch (...) {  // no more threads: the ones started (and the caller) do the work
  }
  worker();
  for (auto& t : pool) t.join();
  if (first_error) std::rethrow_exception(first_error);
}

void parallel_for(std::size_t n, int threads, const std::function<void(std::size_t)>& fn,
                  const ParallelOptions& opt) {
  parallel_workers(
      n, threads,
      [&](const TakeIndex& take) {
        for (std::size_t i; take(i);) fn(i);
      },
      opt);
}

}  // namespace ru::util
