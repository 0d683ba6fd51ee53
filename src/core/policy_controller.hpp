#pragma once
// Controllers of the whisker task from a loaded policy (rl::Policy, a policy file or a run's final
// model). A feed-forward policy maps each observation to its mean action on its own; a recurrent
// one (ppo.policy = "gru") carries the actor's hidden state through an episode, zero at its start.
// So a controller made here serves ONE episode, and evaluations, whose episodes run in parallel,
// take a factory that makes one per episode.
#include <filesystem>
#include <memory>

#include "core/evaluation.hpp"
#include "core/task_config.hpp"
#include "rl/policy_file.hpp"

namespace codesign::core {

// A policy file (rl::Policy) for the task: the one check that a policy fits the task's
// observation (its size, with the history) and its one action; InputError naming the file and
// both sizes otherwise. (`codesign check --config` adds the training-side rules: policy kind and
// layer sizes.)
std::shared_ptr<const rl::Policy> load_task_policy(const std::filesystem::path& policy_file, const TaskConfig& task);

// The deterministic policy for one episode (the mean action, unclipped).
Controller episode_controller(std::shared_ptr<const rl::Policy> policy);
// A fresh episode_controller for every episode (the sensors are not read: the policy sees only
// its observation).
ControllerFactory policy_factory(std::shared_ptr<const rl::Policy> policy);

}  // namespace codesign::core
