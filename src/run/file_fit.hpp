#pragma once
// The rules by which a file a user brings fits a run config (`codesign check FILE --config C`,
// docs/reliability.md): a policy file's kind, observation and layer sizes; a checkpoint's
// config fingerprint and network sizes; the surfaces a whisker mesh must carry. Each rule throws one InputError naming the file, the
// field and the config key it contradicts. (The evaluation's own check, that a policy fits
// the task's observation, is load_task_policy in policy_controller.hpp.)
#include <string>

#include "fem/mesh.hpp"
#include "rl/policy_file.hpp"
#include "run/checkpoint.hpp"
#include "run/run_config.hpp"

namespace codesign::run {

// Throws unless the policy file's contents `p` (read from `file`) fit the run config `c` (read
// from `config_file`): policy kind and GRU size, observation size, one action, actor and critic
// hidden sizes, privileged critic inputs.
void check_policy_fits(const rl::PolicyFileContents& p, const std::string& file, const RunConfig& c,
                       const std::string& config_file);

// The checkpoint in `file`, read against the fingerprint of the run config `c` (from
// `config_file`), whose network sizes must be the config's.
Checkpoint load_fitting_checkpoint(const std::string& file, const RunConfig& c, const std::string& config_file);

// Throws unless the mesh read from `file` carries the surfaces a whisker needs: triangles in the
// physical surfaces "base" (clamped), "tip" and "chamber_1", at most two chambers.
void check_whisker_mesh(const fem::TetMesh& m, const std::string& file);

// "[a, b, c]" (layer sizes as the messages above and `codesign check` print them).
std::string sizes_text(const std::vector<int>& v);

}  // namespace codesign::run
