#include "codesign/policy_controller.hpp"

#include <utility>

namespace codesign::coopt {

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

}  // namespace codesign::coopt
