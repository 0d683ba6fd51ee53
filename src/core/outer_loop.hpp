#pragma once
// Algorithm 1 of the paper: co-optimisation of design and control.
//
// One iteration k (iterate()):
//   1. sample ψ designs d_i = (j_i, p_i) from q_φ (DesignDistribution::sample; the single-design
//      baseline uses its fixed design instead) and a plate phase per environment;
//   2. deploy: one episode per environment, n_steps = decisions per episode (an environment whose
//      episode ends early restarts with the same design until the rollout is full), storing the
//      transitions in the rollout buffer with SB3's semantics (unclipped actions, timeout
//      bootstrapping), then GAE: rl::collect_rollout (rl/rollout.hpp), the gym trainer's loop;
//   3. one PPO update on the ψ × n_steps transitions (ppo.policy = "gru": the recurrent
//      actor-critic, acting with one hidden state per environment reset at each episode start, and
//      rl::recurrent_ppo_update over whole environment columns, each one episode from reset);
//   4. the return of each environment's first episode, R_{d_i}, feeds Algorithm 2;
//   5. t += ψ · n_steps, k += 1.
// Steps 3 and 4 share no state, so 4 runs first: with whole rollouts on MPI ranks the next
// iteration's designs are then drawn before the update (same stream, same order) and the ranks
// start them while rank 0 updates (RunAhead::prestart).
// The run ends when t ≥ total_timesteps. Everything that defines the future of the loop is in
// LoopState (a checkpoint holds it): restoring it and iterating gives bit-identical results.
//
// Random streams, all split from Rng(seed) in this order: network init, action sampling,
// minibatch shuffling, design sampling (designs and plate phases).
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/codesign_config.hpp"
#include "core/design_distribution.hpp"
#include "core/env_pool.hpp"
#include "core/task_config.hpp"
#include "rl/actor_critic.hpp"
#include "rl/adam.hpp"
#include "rl/obs_normalizer.hpp"
#include "rl/policy_file.hpp"
#include "rl/ppo.hpp"
#include "rl/recurrent_actor_critic.hpp"
#include "rl/rng.hpp"
#include "rl/rollout_buffer.hpp"

namespace codesign::core {

struct LoopConfig {
  TaskConfig task;
  CodesignConfig codesign;
  rl::PpoConfig ppo;
};

// The distribution settings of a co-design config.
DistributionConfig distribution_config(const CodesignConfig& c, const TaskConfig& task);
// The fixed design of the single-design baseline: (j, p1, p2) with p2 = 0 for one chamber.
DesignSample single_design(const CodesignConfig& c);
// Chambers of each of the 110 designs.
std::vector<int> design_chambers();

// One finished (or, at the end of a rollout, cut) episode of an iteration.
struct EpisodeRecord {
  int env = 0;
  EpisodeSetup setup;
  double episode_return = 0.0;
  int decisions = 0;
  int in_band = 0;
  std::string reason;        // termination/truncation reason, or "rollout_end" if cut
  bool first = false;        // the environment's first episode of the iteration (fed to Alg. 2)
};

struct IterationReport {
  int k = 0;                       // iteration index (0-based) just completed
  std::int64_t t = 0;              // timesteps after it
  Phase phase = Phase::Exploration;  // phase the designs were sampled in
  double beta = 0.0;               // β(t) after the update
  std::vector<DesignSample> samples;
  std::vector<double> returns;     // R_{d_i}: return of environment i's first episode (fed to Alg. 2)
  std::vector<EpisodeRecord> episodes;
  rl::PpoStats ppo;
  double learning_rate = 0.0;
  double collect_s = 0.0, update_s = 0.0, distribution_s = 0.0;
  double policy_s = 0.0;           // part of collect_s spent in the policy (act/value)
};

// Everything that defines the loop's future (what a checkpoint must hold).
struct LoopState {
  int k = 0;
  std::int64_t t = 0;
  // The MLPs of actor and critic (after their GRUs with ppo.policy = "gru") and log_std.
  Eigen::VectorXf actor, critic, log_std;
  // ppo.policy = "gru": the parameters of the two GRUs; empty otherwise.
  Eigen::VectorXf actor_gru, critic_gru;
  std::int64_t adam_steps = 0;
  std::vector<Eigen::VectorXf> adam_m, adam_v;
  std::string rng_act, rng_update, rng_design;
  DistributionState distribution;
  // Running observation statistics (ppo.normalize_observations); empty when off.
  Eigen::VectorXd obs_mean, obs_var;
  double obs_count = 0.0;
};

// The feed-forward model of ppo.policy = "mlp" for `envs`, its parameters zero, at the configured
// matrix-product precision (what OuterLoop trains; MPI ranks run rollouts with a copy); an empty
// one with "gru".
rl::ActorCritic feed_forward_model(const LoopConfig& c, const EnvPool& envs);
// Whether the loop's rollouts may run whole where the environments are (run_ahead.hpp): a
// feed-forward policy and no observation statistics.
bool whole_rollouts_allowed(const LoopConfig& c);

class OuterLoop {
 public:
  OuterLoop(const LoopConfig& config, std::unique_ptr<EnvPool> envs);

  IterationReport iterate();
  bool finished() const { return t_ >= config_.codesign.total_timesteps; }

  LoopState state() const;
  // Throws std::invalid_argument if the state does not fit this loop's sizes.
  void restore(const LoopState& s);

  const LoopConfig& config() const { return config_; }
  // The feed-forward model (ppo.policy = "mlp"; empty with "gru").
  const rl::ActorCritic& model() const { return model_; }
  // The recurrent model (ppo.policy = "gru"), else null.
  const rl::RecurrentActorCritic* recurrent_model() const { return recurrent_ ? &*recurrent_ : nullptr; }
  // What policy.bin holds: the trained model, whichever kind, and obs_normalization().
  rl::PolicyFileContents policy_contents() const;
  // The frozen observation normalisation the policy acts after (ppo.normalize_observations), of
  // the actor's components only (a privileged critic's features are not the policy's input);
  // nullopt when off.
  std::optional<rl::ObsNormalization> obs_normalization() const;
  const DesignDistribution& distribution() const { return distribution_; }
  DesignDistribution& distribution() { return distribution_; }
  std::int64_t timesteps() const { return t_; }
  int iteration() const { return k_; }
  EnvPool& envs() { return *envs_; }
  // The last rollout (observations as the policy saw them, actions, rewards, ...).
  const rl::RolloutBuffer& buffer() const { return buffer_; }

  // With ppo.policy = "gru": called during each rollout after every decision of environment 0
  // with the decision's index in the episode, the episode's design and the GRU hidden states of
  // the actor and the critic after that decision (telemetry; never called for the MLP). Must not
  // throw. An empty function turns it off.
  using MemoryObserver = std::function<void(int decision, int design, const Eigen::VectorXf& actor_h,
                                            const Eigen::VectorXf& critic_h)>;
  void set_memory_observer(MemoryObserver observer) { memory_observer_ = std::move(observer); }

 private:
  // Iteration k's designs and setups (plate phases, faults), from design_rng_.
  std::vector<DesignSample> sample_designs(int k, std::vector<EpisodeSetup>& setups);
  // The next iteration's designs when they were drawn before this iteration's PPO update, for the
  // pool to start them during it (RunAhead::prestart); design_rng_'s state before that draw, which
  // state() saves, so a resumed run draws them again.
  struct NextDesigns {
    std::vector<DesignSample> samples;
    std::vector<EpisodeSetup> setups;
    std::string rng_before;
  };
  std::optional<NextDesigns> next_;

  LoopConfig config_;
  std::unique_ptr<EnvPool> envs_;
  rl::ActorCritic model_;
  std::optional<rl::RecurrentActorCritic> recurrent_;
  rl::Adam optimizer_;
  rl::RolloutBuffer buffer_;
  rl::Rng act_rng_, update_rng_, design_rng_;
  std::optional<rl::RunningObsStats> obs_stats_;
  DesignDistribution distribution_;
  int k_ = 0;
  std::int64_t t_ = 0;
  MemoryObserver memory_observer_;
};

}  // namespace codesign::core
