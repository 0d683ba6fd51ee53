#pragma once
// Controllers of the whisker task from a loaded policy (rl::Policy, a policy file or a run's final
// model). A feed-forward policy maps each observation to its mean action on its own; a recurrent
// one (ppo.policy = "gru") carries the actor's hidden state through an episode, zero at its start.
// So a controller made here serves ONE episode, and evaluations, whose episodes run in parallel,
// take a factory that makes one per episode.
#include <memory>

#include "codesign/evaluation.hpp"
#include "rl/policy_file.hpp"

namespace codesign::coopt {

// The deterministic policy for one episode (the mean action, unclipped).
Controller episode_controller(std::shared_ptr<const rl::Policy> policy);
// A fresh episode_controller for every episode (the sensors are not read: the policy sees only
// its observation).
ControllerFactory policy_factory(std::shared_ptr<const rl::Policy> policy);

}  // namespace codesign::coopt
