#include "io/config/gym_config.hpp"

#include "io/config/table_keys.hpp"

#include <cstdint>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace codesign::io {

rl::PpoConfig read_ppo_config(TableReader& t, const rl::PpoConfig& d) {
  rl::PpoConfig c = d;
  KeyReader r(t);
  rl::describe_ppo_table(r, c);
  return c;
}

GymTrainConfig read_gym_config(TableReader& root) {
  GymTrainConfig g;
  read_keys(root, "env", [&](auto& v) { describe_env_table(v, g); });
  TableReader ppo = root.table("ppo");
  g.trainer.ppo = read_ppo_config(ppo);
  ppo.finish();
  if (g.trainer.ppo.privileged_critic)
    ppo.fail("privileged_critic", "value true is not allowed here: the gym tasks supply no privileged "
                                  "features (only the whisker co-design does); allowed: false");
  const std::int64_t rollout = static_cast<std::int64_t>(g.trainer.ppo.n_steps) * g.trainer.n_envs;
  if (g.trainer.ppo.batch_size > rollout)
    ppo.fail("batch_size", "value " + std::to_string(g.trainer.ppo.batch_size) +
                               " is out of range; allowed [1, n_steps * env.n_envs = " +
                               std::to_string(rollout) + "]");
  read_keys(root, "train", [&](auto& v) { describe_train_table(v, g); });
  root.finish();
  return g;
}

GymTrainConfig load_gym_config(const std::string& path) {
  TableReader root = TableReader::from_file(path);
  return read_gym_config(root);
}

}  // namespace codesign::io
