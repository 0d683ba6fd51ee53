#include "core/policy_controller.hpp"

#include <string>
#include <utility>

#include "base/errors.hpp"
#include "core/whisker_env.hpp"

namespace codesign::core {

std::shared_ptr<const rl::Policy> load_task_policy(const std::filesystem::path& policy_file, const TaskConfig& task) {
  auto policy = std::make_shared<const rl::Policy>(rl::Policy::load(policy_file));
  if (policy->obs_dim() != observation_dim(task) || policy->act_dim() != 1)
    throw InputError(policy_file.string() + ": the policy takes " + std::to_string(policy->obs_dim()) +
                     " observations and gives " + std::to_string(policy->act_dim()) + " actions; the task's \"" +
                     to_string(task.observation) + "\" observation with history " +
                     std::to_string(task.history) + " has " +
                     std::to_string(observation_dim(task)) + " and 1 action");
  return policy;
}

Controller episode_controller(std::shared_ptr<const rl::Policy> policy) {
  if (!policy->recurrent())
    return [policy = std::move(policy)](const Eigen::VectorXd& obs) { return policy->act_deterministic(obs)[0]; };
  // The episode keeps a pointer to the policy, which the shared_ptr keeps alive.
  auto episode = std::make_shared<rl::Policy::Episode>(policy->begin_episode());
  return [policy = std::move(policy), episode](const Eigen::VectorXd& obs) { return episode->act(obs)[0]; };
}

ControllerFactory policy_factory(std::shared_ptr<const rl::Policy> policy) {
  return [policy = std::move(policy)] {
    return FeedbackController(
        [controller = episode_controller(policy)](const Eigen::VectorXd& obs, const fem::Sensors&) {
          return controller(obs);
        });
  };
}

}  // namespace codesign::core
