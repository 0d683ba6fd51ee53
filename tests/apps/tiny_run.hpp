#pragma once
// The run configs of the command-line tests: a co-design run small enough to finish in seconds
// (a few designs x a few decisions per iteration, tiny networks, float32 products so the result
// does not depend on the CPU), every phase of Algorithm 2. A test sets the fields it cares about
// and appends any tables of its own; toml() writes one key per line, so tests may edit a line
// of the text by string replacement.
#include <string>

namespace codesign::test {

struct TinyRun {
  int episode_steps = 25;
  std::string observation = "proprioceptive";  // "" leaves the key out (the default, "paper")
  int n_steps = 5;
  int batch_size = 8;
  int n_epochs = 2;
  std::string hidden = "[16, 16]";  // actor and critic
  int total_timesteps = 240;
  int designs_per_update = 4;
  int exploration_end = 80;
  int exploitation_start = 160;
  std::string beta_end;  // "" leaves the key out
  int eval_episodes = 3;
  // The fixed-angle reference on d* after the run (codesign.fixed_theta_phases, default 10): two
  // tuning phases keep its code path in every run at a fifth of its cost (under the sanitizers it
  // was over a quarter of a run's time).
  int fixed_theta_phases = 2;
  int checkpoint_every = 40;
  int seed = 11;
  std::string task_extra;  // more [task] keys, one per line
  std::string tables;      // whole tables appended at the end ([faults], [sim], [render], ...)

  // Two decisions per episode and 4-unit networks: for tests that only need a run to exist.
  static TinyRun minimal() {
    TinyRun r;
    r.episode_steps = 10;
    r.n_steps = 2;
    r.batch_size = 4;
    r.n_epochs = 1;
    r.hidden = "[4]";
    return r;
  }

  std::string toml() const {
    std::string t = "[scene]\nsettle_steps = 5\n[task]\nepisode_steps = " + std::to_string(episode_steps) +
                    "\naction_hold_steps = 5\n";
    if (!observation.empty()) t += "observation = \"" + observation + "\"\n";
    t += task_extra;
    t += "[ppo]\nn_steps = " + std::to_string(n_steps) + "\nbatch_size = " + std::to_string(batch_size) +
         "\nn_epochs = " + std::to_string(n_epochs) + "\nactor_hidden = " + hidden +
         "\ncritic_hidden = " + hidden + "\nmatmul_precision = \"float32\"\n";
    t += "[codesign]\ntotal_timesteps = " + std::to_string(total_timesteps) +
         "\ndesigns_per_update = " + std::to_string(designs_per_update) +
         "\nexploration_end = " + std::to_string(exploration_end) +
         "\nexploitation_start = " + std::to_string(exploitation_start) + "\n";
    if (!beta_end.empty()) t += "beta_end = " + beta_end + "\n";
    t += "eval_episodes = " + std::to_string(eval_episodes) +
         "\nfixed_theta_phases = " + std::to_string(fixed_theta_phases) +
         "\ncheckpoint_every = " + std::to_string(checkpoint_every) + "\nseed = " + std::to_string(seed) + "\n";
    return t + tables;
  }
};

}  // namespace codesign::test
