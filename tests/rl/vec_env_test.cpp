// VecEnv auto-reset semantics (SB3 VecEnv), terminal observations, and determinism across
// thread counts; ThreadPool basics.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include "rl/pendulum.hpp"
#include "rl/rng.hpp"
#include "rl/thread_pool.hpp"
#include "rl/vec_env.hpp"

namespace codesign::rl {
namespace {

// obs = [t, episode, index]; reward = action; episode ends after `length` steps, by termination
// when `terminate` is set, else by truncation.
class CountingEnv final : public Env {
 public:
  CountingEnv(std::size_t index, int length, bool terminate)
      : index_(index), length_(length), terminate_(terminate) {
    spec_.observation.low = Eigen::Vector3d::Constant(-1e9);
    spec_.observation.high = Eigen::Vector3d::Constant(1e9);
    spec_.action.low = Eigen::VectorXd::Constant(1, -1.0);
    spec_.action.high = Eigen::VectorXd::Constant(1, 1.0);
  }
  const EnvSpec& spec() const override { return spec_; }
  Eigen::VectorXd reset(std::optional<std::uint64_t> seed) override {
    if (seed) seeded_with = *seed;
    t_ = 0;
    ++episode_;
    return obs();
  }
  StepResult step(const Eigen::VectorXd& a) override {
    ++t_;
    StepResult r;
    r.obs = obs();
    r.reward = a(0);
    if (t_ == length_) {
      (terminate_ ? r.terminated : r.truncated) = true;
      r.reason = terminate_ ? "goal" : "time_limit";
    }
    return r;
  }
  std::uint64_t seeded_with = ~0ull;

 private:
  Eigen::VectorXd obs() const {
    return Eigen::Vector3d(t_, episode_, static_cast<double>(index_));
  }
  EnvSpec spec_;
  std::size_t index_;
  int length_;
  bool terminate_;
  int t_ = 0;
  int episode_ = 0;
};

TEST(VecEnv, AutoResetKeepsTerminalObservation) {
  // env 0 truncates every 3 steps, env 1 terminates every 2 steps.
  std::vector<CountingEnv*> raw;
  EnvFactory f = [&](std::size_t i) {
    auto e = std::make_unique<CountingEnv>(i, i == 0 ? 3 : 2, i == 1);
    raw.push_back(e.get());
    return e;
  };
  VecEnv venv(f, 2, 100, 1);
  Eigen::MatrixXd obs = venv.reset();
  EXPECT_EQ(raw[0]->seeded_with, 100u);
  EXPECT_EQ(raw[1]->seeded_with, 101u);
  EXPECT_EQ(obs.col(0), Eigen::Vector3d(0, 1, 0));
  EXPECT_EQ(obs.col(1), Eigen::Vector3d(0, 1, 1));

  Eigen::MatrixXd a(1, 2);
  a << 0.25, -0.5;
  const VecStepResult* r = &venv.step(a);  // t = 1 for both
  EXPECT_EQ(r->rewards(0), 0.25);
  EXPECT_EQ(r->rewards(1), -0.5);
  EXPECT_FALSE(r->done(0));
  EXPECT_FALSE(r->done(1));
  EXPECT_FALSE(r->terminal_obs[0].has_value());

  r = &venv.step(a);  // t = 2: env 1 terminates
  EXPECT_FALSE(r->done(0));
  EXPECT_TRUE(r->terminated[1]);
  EXPECT_FALSE(r->truncated[1]);
  ASSERT_TRUE(r->terminal_obs[1].has_value());
  EXPECT_EQ(*r->terminal_obs[1], Eigen::Vector3d(2, 1, 1));  // last obs of episode 1
  EXPECT_EQ(r->obs.col(1), Eigen::Vector3d(0, 2, 1));        // first obs of episode 2
  EXPECT_EQ(r->reasons[1], "goal");
  EXPECT_EQ(r->obs.col(0), Eigen::Vector3d(2, 1, 0));
  EXPECT_EQ(raw[1]->seeded_with, 101u);  // auto-reset does not re-seed

  r = &venv.step(a);  // t = 3: env 0 truncates; env 1 at t = 1 of episode 2
  EXPECT_TRUE(r->truncated[0]);
  EXPECT_FALSE(r->terminated[0]);
  ASSERT_TRUE(r->terminal_obs[0].has_value());
  EXPECT_EQ(*r->terminal_obs[0], Eigen::Vector3d(3, 1, 0));
  EXPECT_EQ(r->obs.col(0), Eigen::Vector3d(0, 2, 0));
  EXPECT_FALSE(r->done(1));
  EXPECT_FALSE(r->terminal_obs[1].has_value());  // cleared after the step that ended it
  EXPECT_TRUE(r->reasons[1].empty());
}

TEST(VecEnv, RejectsBadActionShape) {
  VecEnv venv(pendulum_factory(), 3, 0, 1);
  venv.reset();
  EXPECT_THROW(venv.step(Eigen::MatrixXd::Zero(1, 2)), std::invalid_argument);
  EXPECT_THROW(venv.step(Eigen::MatrixXd::Zero(2, 3)), std::invalid_argument);
}

// Runs `steps` steps of `n` pendulums with actions from a fixed stream; returns every obs and
// reward concatenated.
std::vector<double> pendulum_rollout(std::size_t n_threads, std::size_t n, int steps) {
  VecEnv venv(pendulum_factory(), n, 42, n_threads);
  std::vector<double> out;
  Eigen::MatrixXd obs = venv.reset();
  out.insert(out.end(), obs.data(), obs.data() + obs.size());
  Rng rng(9);
  Eigen::MatrixXd a(1, static_cast<Eigen::Index>(n));
  for (int t = 0; t < steps; ++t) {
    for (Eigen::Index i = 0; i < a.cols(); ++i) a(0, i) = -3.0 + 6.0 * rng.uniform();
    const VecStepResult& r = venv.step(a);
    out.insert(out.end(), r.obs.data(), r.obs.data() + r.obs.size());
    out.insert(out.end(), r.rewards.data(), r.rewards.data() + r.rewards.size());
    for (std::size_t i = 0; i < n; ++i)
      if (r.terminal_obs[i]) out.insert(out.end(), r.terminal_obs[i]->data(),
                                        r.terminal_obs[i]->data() + 3);
  }
  return out;
}

TEST(VecEnv, BitIdenticalForOneAndFourThreads) {
  // 450 steps cross two episode boundaries (200, 400), so auto-reset is covered.
  const std::vector<double> one = pendulum_rollout(1, 8, 450);
  const std::vector<double> four = pendulum_rollout(4, 8, 450);
  ASSERT_EQ(one.size(), four.size());
  EXPECT_EQ(one, four);  // exact equality of every double
  // And environments differ from each other (seeded seed + i).
  EXPECT_NE(one[0], one[3]);
}

TEST(ThreadPool, RunsEveryIndexOnceAndRethrows) {
  for (std::size_t threads : {1u, 2u, 4u}) {
    ThreadPool pool(threads);
    EXPECT_EQ(pool.size(), threads);
    for (std::size_t n : {0u, 1u, 7u, 1000u}) {
      std::vector<std::atomic<int>> hits(n);
      pool.parallel_for(n, [&](std::size_t i) { hits[i].fetch_add(1); });
      for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(hits[i].load(), 1) << threads << " " << i;
    }
    EXPECT_THROW(pool.parallel_for(10,
                                   [](std::size_t i) {
                                     if (i == 5) throw std::runtime_error("boom");
                                   }),
                 std::runtime_error);
    // Still usable after an exception.
    std::atomic<int> sum{0};
    pool.parallel_for(10, [&](std::size_t i) { sum += static_cast<int>(i); });
    EXPECT_EQ(sum.load(), 45);
  }
}

TEST(ThreadPool, OrderedRunsEveryListedIndexOnceClaimingInTheGivenOrder) {
  const std::vector<std::size_t> order{6, 2, 9, 0, 4, 1, 8, 3, 7, 5};
  for (std::size_t threads : {1u, 2u, 4u}) {
    ThreadPool pool(threads);
    std::vector<std::atomic<int>> hits(order.size());
    std::mutex m;
    std::vector<std::size_t> started;
    pool.parallel_for_ordered(order, [&](std::size_t i) {
      {
        std::lock_guard lock(m);
        started.push_back(i);
      }
      hits[i].fetch_add(1);
    });
    for (std::size_t i = 0; i < order.size(); ++i) ASSERT_EQ(hits[i].load(), 1) << threads << " " << i;
    // With one thread the calls run exactly in the listed order. With more, indices are claimed
    // in that order, but two threads may record their starts swapped: not checked.
    if (threads == 1) {
      EXPECT_EQ(started, order);
    }
    EXPECT_THROW(pool.parallel_for_ordered(order,
                                           [](std::size_t i) {
                                             if (i == 4) throw std::runtime_error("boom");
                                           }),
                 std::runtime_error);
  }
}

TEST(ThreadPool, AJobTakesNoMoreThreadsThanItMayUse) {
  // Each call holds its thread for 20 ms, long enough for every woken worker to join the job: with
  // the cap broken, more threads than allowed would take calls (all 4 of the pool). Checked: the
  // threads that ran calls, and the most calls running at once, are at most the cap.
  ThreadPool pool(4);
  const std::vector<std::size_t> order{0, 1, 2, 3, 4, 5, 6, 7};
  for (std::size_t cap : {1u, 2u, 3u, 4u, 0u}) {
    std::mutex m;
    std::set<std::thread::id> ids;
    int running = 0, most = 0;
    std::vector<std::atomic<int>> hits(order.size());
    pool.parallel_for_ordered(order, [&](std::size_t i) {
      {
        std::lock_guard lock(m);
        ids.insert(std::this_thread::get_id());
        most = std::max(most, ++running);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      {
        std::lock_guard lock(m);
        --running;
      }
      hits[i].fetch_add(1);
    }, cap);
    const std::size_t allowed = cap == 0 ? 4 : cap;
    for (std::size_t i = 0; i < order.size(); ++i) ASSERT_EQ(hits[i].load(), 1) << cap << " " << i;
    EXPECT_LE(ids.size(), allowed) << "cap " << cap;
    EXPECT_LE(static_cast<std::size_t>(most), allowed) << "cap " << cap;
    if (cap == 1) {
      EXPECT_EQ(*ids.begin(), std::this_thread::get_id());  // on the caller alone
    }
  }
}

TEST(ThreadPool, ARecountLetsMoreThreadsIntoTheCallUnderWay) {
  // The call starts on the caller alone (max_threads 1); after the caller's first index the recount
  // allows 2 threads, so a worker joins the call still running (7 more indices of 20 ms each are
  // left for it: ample time to wake), and never a third. The recount runs on the caller only.
  ThreadPool pool(4);
  const std::vector<std::size_t> order{0, 1, 2, 3, 4, 5, 6, 7};
  std::mutex m;
  std::set<std::thread::id> ids;
  std::vector<std::atomic<int>> hits(order.size());
  const std::thread::id caller = std::this_thread::get_id();
  int recounts = 0;
  bool recount_elsewhere = false;
  pool.parallel_for_ordered(
      order,
      [&](std::size_t i) {
        {
          std::lock_guard lock(m);
          ids.insert(std::this_thread::get_id());
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        hits[i].fetch_add(1);
      },
      1,
      [&]() -> std::size_t {
        if (std::this_thread::get_id() != caller) recount_elsewhere = true;
        ++recounts;
        return 2;
      });
  for (std::size_t i = 0; i < order.size(); ++i) ASSERT_EQ(hits[i].load(), 1) << i;
  EXPECT_EQ(ids.size(), 2u);
  EXPECT_GE(recounts, 1);
  EXPECT_FALSE(recount_elsewhere);
  // An exception of the recount comes back to the caller after the calls under way.
  EXPECT_THROW(pool.parallel_for_ordered(
                   order, [](std::size_t) {}, 1, []() -> std::size_t { throw std::runtime_error("recount"); }),
               std::runtime_error);
}

}  // namespace
}  // namespace codesign::rl
