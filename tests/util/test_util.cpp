// The utility layer (rayunits/util/): parallel loop, process launcher, interrupt flag, commit
// lookup, shell quoting.
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include "rayunits/util/git.hpp"
#include "rayunits/util/interrupt.hpp"
#include "rayunits/util/parallel.hpp"
#include "rayunits/util/process.hpp"

namespace fs = std::filesystem;
using namespace ru::util;

namespace {

TEST(UtilParallel, EveryIndexOnce) {
  for (int threads : {0, 1, 2, 7}) {
    std::vector<std::atomic<int>> hits(1000);
    parallel_for(hits.size(), threads, [&](size_t i) { hits[i]++; });
    for (auto& h : hits) ASSERT_EQ(h.load(), 1) << threads;
  }
  parallel_for(0, 4, [](size_t) { FAIL(); });
}

TEST(UtilParallel, OneThreadRunsOnTheCallerInOrder) {
  std::vector<size_t> order;
  const auto me = std::this_thread::get_id();
  parallel_for(50, 1, [&](size_t i) {
    EXPECT_EQ(std::this_thread::get_id(), me);
    order.push_back(i);
  });
  ASSERT_EQ(order.size(), 50u);
  for (size_t i = 0; i < order.size(); ++i) EXPECT_EQ(order[i], i);
}

TEST(UtilParallel, FirstExceptionIsRethrownAndStopsTheHandout) {
  // Jobs after 10 take 1 ms each, so the other workers cannot race through the whole range in the
  // moment between job 10's throw and the stop of the handout (without it this test was flaky on
  // a loaded machine: all 100,000 trivial jobs ran while the throwing worker was descheduled).
  std::atomic<int> ran{0};
  EXPECT_THROW(parallel_for(100000, 3,
                            [&](size_t i) {
                              ++ran;
                              if (i == 10) throw std::runtime_error("job 10");
                              if (i > 10) std::this_thread::sleep_for(std::chrono::milliseconds(1));
                            }),
               std::runtime_error);
  EXPECT_LT(ran.load(), 100000);
}

TEST(UtilParallel, WorkersKeepStateStopAndProgress) {
  std::mutex mu;
  size_t total = 0, bodies = 0, last_done = 0;
  ParallelOptions po;
  po.progress_period = 0;
  po.progress = [&](size_t d, size_t n) {
    EXPECT_EQ(n, 200u);
    last_done = std::max(last_done, d);
  };
  parallel_workers(
      200, 2,
      [&](const TakeIndex& take) {
        size_t mine = 0;
        for (size_t i; take(i);) ++mine;
        std::lock_guard<std::mutex> g(mu);
        total += mine;
        ++bodies;
      },
      po);
  EXPECT_EQ(total, 200u);
  EXPECT_EQ(bodies, 2u);
  EXPECT_GT(last_done, 0u);
  std::atomic<int> ran{0};
  po = {};
  po.stop = [&] { return ran.load() >= 5; };
  parallel_for(1000, 1, [&](size_t) { ++ran; }, po);
  EXPECT_EQ(ran.load(), 5);
}

TEST(UtilProcess, CapturesOutputAndExitStatus) {
  ProcessOptions o;
  o.out = Redirect::capture();
  o.err = Redirect::capture();
  ProcessResult r = run_process({"sh", "-c", "echo out; echo err >&2; exit 3"}, o);
  EXPECT_TRUE(r.started);
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_EQ(r.status(), 3);
  EXPECT_EQ(r.out, "out\n");
  EXPECT_EQ(r.err, "err\n");
  // no shell: the argument is one word, metacharacters included
  r = run_process({"printf", "%s|", "a b", "$HOME;x"}, o);
  EXPECT_EQ(r.out, "a b|$HOME;x|");
  o.err_to_out = true;
  r = run_process({"sh", "-c", "echo a; echo b >&2"}, o);
  EXPECT_EQ(r.out, "a\nb\n");
  EXPECT_EQ(r.err, "");
}

TEST(UtilProcess, LargeOutputDoesNotDeadlock) {
  ProcessOptions o;
  o.out = Redirect::capture();
  o.err = Redirect::capture();
  ProcessResult r = run_process({"sh", "-c", "head -c 300000 /dev/zero; head -c 200000 /dev/zero >&2"}, o);
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.out.size(), 300000u);
  EXPECT_EQ(r.err.size(), 200000u);
}

TEST(UtilProcess, TimeoutKillsTheWholeGroup) {
  const fs::path flag = fs::temp_directory_path() / ("ru_util_grandchild_" + std::to_string(::getpid()));
  fs::remove(flag);
  ProcessOptions o;
  o.timeout_s = 0.3;
  const auto t0 = std::chrono::steady_clock::now();
  // the grandchild would write the flag after 1.5 s if the group were not killed
  ProcessResult r = run_process({"sh", "-c", "(sleep 1.5; touch " + flag.string() + ") & sleep 30"}, o);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_TRUE(r.timed_out);
  EXPECT_EQ(r.exit_code, -1);
  EXPECT_EQ(r.term_signal, SIGKILL);
  EXPECT_LT(s, 5.0);
  std::this_thread::sleep_for(std::chrono::milliseconds(1800));
  EXPECT_FALSE(fs::exists(flag)) << "the grandchild survived the timeout";
  fs::remove(flag);
}

TEST(UtilProcess, NotFoundFilesAndCwd) {
  ProcessResult r = run_process({"ru-no-such-program-xyz"});
  EXPECT_FALSE(r.started);
  EXPECT_EQ(r.exit_code, 127);
  EXPECT_NE(r.error.find("ru-no-such-program-xyz"), std::string::npos);
  const fs::path dir = fs::temp_directory_path() / ("ru_util_proc_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  ProcessOptions o;
  o.cwd = dir.string();
  o.out = Redirect::file((dir / "log").string());
  o.err_to_out = true;
  EXPECT_EQ(run_process({"sh", "-c", "pwd; echo e >&2"}, o).exit_code, 0);
  o.out.append = true;
  EXPECT_EQ(run_process({"echo", "again"}, o).exit_code, 0);
  std::ifstream in(dir / "log");
  std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_EQ(text, fs::canonical(dir).string() + "\ne\nagain\n");
  o.out = Redirect::file((dir / "no" / "such" / "log").string());
  EXPECT_THROW(run_process({"true"}, o), ProcessError);
  o.out = Redirect::capture();
  o.cwd = (dir / "missing").string();
  r = run_process({"true"}, o);
  EXPECT_FALSE(r.started);
  EXPECT_EQ(r.exit_code, 127);
  fs::remove_all(dir);
  EXPECT_EQ(run_foreground({"true"}), 0);
  EXPECT_EQ(run_foreground({"false"}), 1);
  EXPECT_EQ(run_foreground({"ru-no-such-program-xyz"}), 127);
}

TEST(UtilProcess, ChildPipes) {
  ProcessOptions o;
  o.in = Redirect::capture();
  o.out = Redirect::capture();
  Child c({"cat"}, o);
  ASSERT_TRUE(c.started());
  const std::string msg = "hello\n";
  ASSERT_EQ(::write(c.in_fd(), msg.data(), msg.size()), static_cast<ssize_t>(msg.size()));
  char buf[6];
  size_t got = 0;
  while (got < sizeof buf) {
    const ssize_t n = ::read(c.out_fd(), buf + got, sizeof buf - got);
    ASSERT_GT(n, 0);
    got += static_cast<size_t>(n);
  }
  EXPECT_EQ(std::string(buf, 6), msg);
  ASSERT_EQ(::write(c.in_fd(), "rest", 4), 4);
  c.close_in();
  ProcessResult r = c.wait();
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.out, "rest");
}

TEST(UtilProcess, InterruptStopsTheChild) {
  InterruptGuard guard;
  EXPECT_FALSE(interrupted());
  std::thread t([] {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    ::kill(::getpid(), SIGINT);  // the handler only sets the flag
  });
  const auto t0 = std::chrono::steady_clock::now();
  ProcessResult r = run_process({"sleep", "30"});
  t.join();
  EXPECT_TRUE(interrupted());
  EXPECT_TRUE(r.interrupted);
  EXPECT_EQ(r.term_signal, SIGTERM);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
  clear_interrupted();
}

TEST(UtilInterrupt, GuardRestoresTheOldHandler) {
  struct sigaction before {};
  ::sigaction(SIGTERM, nullptr, &before);
  {
    InterruptGuard g;
    ::raise(SIGTERM);
    EXPECT_TRUE(interrupted());
  }
  struct sigaction after {};
  ::sigaction(SIGTERM, nullptr, &after);
  EXPECT_EQ(before.sa_handler, after.sa_handler);
  clear_interrupted();
}

TEST(UtilShell, Quote) {
  EXPECT_EQ(shell_quote("a b"), "'a b'");
  EXPECT_EQ(shell_quote("it's"), "'it'\\''s'");
  EXPECT_EQ(shell_quote(""), "''");
  EXPECT_EQ(shell_join({"python3", "/x/plot.py", "a b", "it's", ""}), "python3 /x/plot.py 'a b' 'it'\\''s' ''");
  // the quoting survives a real shell
  ProcessOptions o;
  o.out = Redirect::capture();
  const std::string nasty = "a 'b' \"c\" $d `e` \\f; g";
  EXPECT_EQ(run_process({"sh", "-c", "printf %s " + shell_quote(nasty)}, o).out, nasty);
}

TEST(UtilGit, CommitOfTheSourceTree) {
  const std::string c = git_commit(RU_SOURCE_DIR);
  if (c == "unknown") GTEST_SKIP() << "no git or not a repository";
  EXPECT_GE(c.size(), 40u);
  EXPECT_EQ(c.substr(0, 40).find_first_not_of("0123456789abcdef"), std::string::npos) << c;
  const auto s = git_commit_info(RU_SOURCE_DIR, true, {"rtl"});
  ASSERT_TRUE(s);
  EXPECT_EQ(c.substr(0, s->hash.size()), s->hash);
  EXPECT_EQ(git_commit("/"), "unknown");
}

}  // namespace
