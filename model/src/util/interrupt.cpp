// rayunits util: SIGINT/SIGTERM handling (see rayunits/util/interrupt.hpp).
#include "rayunits/util/interrupt.hpp"

#include <signal.h>

#include <atomic>

namespace ru::util {

namespace {
std::atomic<bool> g_interrupted{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the signal handler needs a lock-free flag");
extern "C" void ru_util_on_interrupt(int) { g_interrupted.store(true); }

void install(struct sigaction* old_int, struct sigaction* old_term) {
  struct sigaction sa {};
  sa.sa_handler = ru_util_on_interrupt;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0;
  ::sigaction(SIGINT, &sa, old_int);
  ::sigaction(SIGTERM, &sa, old_term);
}
}  // namespace

void install_interrupt_handler() { install(nullptr, nullptr); }
bool interrupted() { return g_interrupted.load(); }
void clear_interrupted() { g_interrupted.store(false); }

struct InterruptGuard::Saved {
  struct sigaction old_int {};
  struct sigaction old_term {};
};

InterruptGuard::InterruptGuard() : saved_(new Saved) {
  clear_interrupted();
  install(&saved_->old_int, &saved_->old_term);
}

InterruptGuard::~InterruptGuard() {
  ::sigaction(SIGINT, &saved_->old_int, nullptr);
  ::sigaction(SIGTERM, &saved_->old_term, nullptr);
  delete saved_;
}

}  // namespace ru::util
