// Cooperative cancellation: a flag set from another thread stops a long training promptly (in
// the bins' worker threads and inside the l1 solver), a set flag stops it at once, scopes nest.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "dd_fixtures.hpp"
#include "inhap/core/cancel.hpp"

namespace inhap::datadriven {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// One large bin: k-means, the r^3 matrix and the l1 solver on many candidates (several seconds).
TrainParams long_params(int bins, int threads) {
  TrainParams p;
  p.bins = bins;
  p.centers = 300;
  p.nonzeros = 300;
  p.seed = 2;
  p.threads = threads;
  return p;
}

TEST(Cancel, ScopesNestAndCheckThrowsOnlyWhenSet) {
  EXPECT_EQ(current_cancel(), nullptr);
  EXPECT_NO_THROW(check_cancel());
  CancelFlag a, b;
  {
    CancelScope sa(&a);
    EXPECT_EQ(current_cancel(), &a);
    {
      CancelScope sb(&b);
      EXPECT_EQ(current_cancel(), &b);
      b.request();
      EXPECT_THROW(check_cancel(), Cancelled);
    }
    EXPECT_EQ(current_cancel(), &a);
    EXPECT_NO_THROW(check_cancel());
  }
  EXPECT_EQ(current_cancel(), nullptr);
}

TEST(Cancel, ASetFlagStopsTrainingAtOnce) {
  const TrainingSet set = test::synthetic_set(3, 4000);
  CancelFlag flag;
  flag.request();
  CancelScope scope(&flag);
  EXPECT_THROW(train_force_model(set, test::small_params()), Cancelled);
}

// Uncancelled, the training takes `full` seconds; cancelled 0.2 s in, it stops within 0.5 s of
// the request, in one bin (the calling thread) or two (a worker thread each).
TEST(Cancel, AFlagSetFromAnotherThreadStopsTrainingPromptly) {
  for (int threads : {1, 2}) {
    SCOPED_TRACE(threads);
    const TrainParams p = long_params(threads, threads);
    // A training long enough for the test to mean anything on a fast or a slow machine: the
    // samples doubled until it takes 1.5 s.
    TrainingSet set;
    double full = 0;
    for (std::size_t n = 16000; n <= 128000 && full <= 1.5; n *= 2) {
      set = test::synthetic_set(4, n);
      const auto t0 = Clock::now();
      (void)train_force_model(set, p);
      full = seconds_since(t0);
    }
    ASSERT_GT(full, 1.5) << "the training must be long for the test to mean anything";

    CancelFlag flag;
    Clock::time_point requested;
    std::thread stopper([&] {
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
      requested = Clock::now();
      flag.request();
    });
    const auto t0 = Clock::now();
    {
      CancelScope scope(&flag);
      EXPECT_THROW(train_force_model(set, p), Cancelled);
    }
    const auto stopped = Clock::now();
    stopper.join();
    const double late = std::chrono::duration<double>(stopped - requested).count();
    std::printf("threads %d: full training %.2f s, stopped %.3f s after the request\n", threads,
                full, late);
    EXPECT_LT(late, 0.5);
    EXPECT_LT(seconds_since(t0), full);
  }
}

}  // namespace
}  // namespace inhap::datadriven
