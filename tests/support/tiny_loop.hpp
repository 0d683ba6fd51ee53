#pragma once
// A co-design loop small enough for unit tests (tests/core and, through test_setup.hpp's
// tiny_run, tests/run): 4 environments, 5 decisions per episode, small networks, all three phases
// within 6 iterations. Only the co-design core's types: the simulator set-up and the loop config.
#include <cstdint>

#include "core/outer_loop.hpp"
#include "fem/simulator.hpp"
#include "fem/whisker_model.hpp"
#include "rl/ppo.hpp"

namespace codesign::test_loops {

struct TinyLoop {
  fem::WhiskerModelSpec spec;
  fem::SceneConfig scene;
  fem::SolverConfig solver;
  core::LoopConfig loop;
};

inline TinyLoop tiny_loop(std::uint64_t seed = 7) {
  TinyLoop s;
  s.scene.settle_steps = 5;
  core::LoopConfig& l = s.loop;
  l.task.episode_steps = 25;
  l.task.action_hold_steps = 5;
  l.task.observation = core::ObservationSet::Proprioceptive;
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
  return s;
}

}  // namespace codesign::test_loops
