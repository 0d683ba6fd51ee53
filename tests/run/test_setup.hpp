#pragma once
// A co-design run small enough for unit tests: 4 environments, 5 decisions per episode, small
// networks, all three phases within 6 iterations.
#include "run/run.hpp"

namespace codesign::run::test {

inline RunSettings tiny_run(std::uint64_t seed = 7) {
  RunSettings s;
  s.scene.settle_steps = 5;
  LoopConfig& l = s.loop;
  l.task.episode_steps = 25;
  l.task.action_hold_steps = 5;
  l.task.observation = ObservationSet::Proprioceptive;
  l.codesign.total_timesteps = 120;  // 6 iterations of 4 x 5
  l.codesign.designs_per_update = 4;
  l.codesign.distribution.exploration_end = 40;
  l.codesign.distribution.exploitation_start = 80;
  l.codesign.distribution.beta_end = 2.0;
  l.codesign.eval_episodes = 3;
  l.codesign.fixed_theta_phases = 2;  // the fixed-angle reference on d*, kept cheap
  l.codesign.checkpoint_every = 20;
  l.codesign.seed = seed;
  l.ppo = rl::paper_ppo_config();
  l.ppo.n_steps = 5;
  l.ppo.batch_size = 8;
  l.ppo.n_epochs = 2;
  l.ppo.actor_hidden = {16, 16};
  l.ppo.critic_hidden = {16, 16};
  l.ppo.matmul_precision = rl::MatmulPrecision::Float32;
  s.config_text = "# tiny test run, seed " + std::to_string(seed) + "\n";
  return s;
}

}  // namespace codesign::run::test
