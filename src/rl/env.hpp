#pragma once
// The environment interface every task implements (Pendulum here, the whisker MDP later).
//
// Semantics follow Gymnasium:
//   reset(seed)  -> first observation. A seed re-seeds the environment's own RNG; no seed continues
//                   the RNG stream (how auto-reset after an episode works).
//   step(action) -> {obs, reward, terminated, truncated, reason}.
//     terminated: the MDP reached a terminal state (no future reward; the value of `obs` is 0).
//     truncated:  the episode was cut for a reason outside the MDP, normally a time limit; the
//                 state is not terminal, so a learner bootstraps from V(obs) (SB3 does).
//   Both may be true; a learner then treats the step as terminated (SB3's
//   "TimeLimit.truncated = truncated and not terminated").
// Actions are given unclipped; an environment must clip (or reject) out-of-bounds actions itself
// if its dynamics need it. The trainer clips to the action bounds before calling step, as SB3 does.
// Observations and actions are float64.
//
// An Env owns all of its state including its RNG, so N environments can be stepped on N threads
// with results independent of the scheduling.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include <Eigen/Core>

namespace codesign::rl {

// A box: one [low, high] interval per component (infinite bounds allowed).
struct BoxSpec {
  Eigen::VectorXd low;
  Eigen::VectorXd high;
  std::size_t dim() const { return static_cast<std::size_t>(low.size()); }
};

struct EnvSpec {
  BoxSpec observation;
  BoxSpec action;
};

struct StepResult {
  Eigen::VectorXd obs;
  double reward = 0.0;
  bool terminated = false;
  bool truncated = false;
  // Why the episode ended, for logs ("time_limit", "lost_contact", ...); empty while running.
  std::string reason;
  bool done() const { return terminated || truncated; }
};

class Env {
 public:
  virtual ~Env() = default;
  virtual const EnvSpec& spec() const = 0;
  virtual Eigen::VectorXd reset(std::optional<std::uint64_t> seed) = 0;
  virtual StepResult step(const Eigen::VectorXd& action) = 0;
};

// Makes the environment with index `index` of a vector of environments (0-based). Each call must
// return an independent object; the index lets a task vary per-environment settings if it wants.
using EnvFactory = std::function<std::unique_ptr<Env>(std::size_t index)>;

// Gymnasium's TimeLimit wrapper: truncates the episode after `max_episode_steps` steps (the
// step counter restarts on reset). A terminated step is not also marked truncated by the wrapper
// unless the limit is reached on that very step (Gymnasium sets both then).
class TimeLimit final : public Env {
 public:
  TimeLimit(std::unique_ptr<Env> inner, int max_episode_steps)
      : inner_(std::move(inner)), max_steps_(max_episode_steps) {}

  const EnvSpec& spec() const override { return inner_->spec(); }
  Eigen::VectorXd reset(std::optional<std::uint64_t> seed) override {
    steps_ = 0;
    return inner_->reset(seed);
  }
  StepResult step(const Eigen::VectorXd& action) override {
    StepResult r = inner_->step(action);
    ++steps_;
    if (steps_ >= max_steps_) {
      r.truncated = true;
      if (r.reason.empty()) r.reason = "time_limit";
    }
    return r;
  }
  int max_episode_steps() const { return max_steps_; }
  int elapsed_steps() const { return steps_; }

 private:
  std::unique_ptr<Env> inner_;
  int max_steps_;
  int steps_ = 0;
};

}  // namespace codesign::rl
