// `codesign check FILE [--config run.toml]`
//
// Reads a file a user brings from elsewhere — a gmsh .msh 4.1 mesh, a policy file, a checkpoint —
// with the same readers the program uses, and prints one line saying what it holds. With
// --config it also checks that the file fits that run config: a policy's network sizes and
// observation size, a checkpoint's config fingerprint and network sizes. A mesh must carry the
// surfaces a whisker needs (base, tip, chamber_1). Writes nothing; any defect is one message
// naming the file and the field, exit status 2.
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "base/errors.hpp"
#include "commands.hpp"
#include "fem/mesh_ops.hpp"
#include "io/msh.hpp"
#include "rl/layer_sizes.hpp"
#include "rl/policy_file.hpp"
#include "run/checkpoint.hpp"
#include "run/file_fit.hpp"
#include "run/run_config.hpp"

namespace codesign::app {

namespace {

struct CheckOptions {
  std::string file;
  std::string config;
};

int check_mesh(const CheckOptions& o) {
  const fem::TetMesh m = io::read_msh_file(o.file);
  const char* need = "; a whisker mesh needs triangles in the physical surfaces \"base\" (clamped), \"tip\" and "
                     "\"chamber_1\" (and \"chamber_2\" for two chambers)";
  if (m.base_faces.empty()) throw InputError(o.file + ": physical group \"base\": no triangles" + need);
  if (m.tip_faces.empty()) throw InputError(o.file + ": physical group \"tip\": no triangles" + need);
  if (m.chamber_faces.empty() || m.chamber_faces[0].empty())
    throw InputError(o.file + ": physical group \"chamber_1\": no triangles" + need);
  if (m.chamber_faces.size() > 2)
    throw InputError(o.file + ": physical group \"chamber_" + std::to_string(m.chamber_faces.size()) +
                     "\": at most 2 chambers (chamber_1, chamber_2) are allowed");
  double volume = 0.0;
  for (std::size_t t = 0; t < m.tets.size(); ++t) volume += fem::tet_volume(m, static_cast<int>(t));
  std::printf("%s: mesh: %zu nodes, %zu tetrahedra, volume %.6g mm^3; faces: base %zu, tip %zu", o.file.c_str(),
              m.nodes.size(), m.tets.size(), volume, m.base_faces.size(), m.tip_faces.size());
  for (std::size_t c = 0; c < m.chamber_faces.size(); ++c)
    std::printf(", chamber_%zu %zu", c + 1, m.chamber_faces[c].size());
  std::printf("\n");
  return 0;
}

int check_policy(const CheckOptions& o) {
  const rl::PolicyFileContents p = rl::load_policy(o.file);
  const rl::MlpT<float>& actor_mlp = p.recurrent ? p.recurrent->actor() : p.model.actor();
  const rl::MlpT<float>& critic_mlp = p.recurrent ? p.recurrent->critic() : p.model.critic();
  const std::vector<int> actor = rl::hidden_sizes(actor_mlp.sizes()), critic = rl::hidden_sizes(critic_mlp.sizes());
  if (!o.config.empty()) run::check_policy_fits(p, o.file, run::read_run_config(o.config), o.config);
  std::printf("%s: policy: obs_dim %d, act_dim %d, %sactor %s, critic %s%s, observation normalisation %s%s\n",
              o.file.c_str(), p.obs_dim(), p.act_dim(),
              p.recurrent ? ("GRU " + std::to_string(p.recurrent->gru_hidden()) + " before each MLP, ").c_str() : "",
              run::sizes_text(actor).c_str(), run::sizes_text(critic).c_str(),
              p.privileged_dim() > 0 ? (" (+" + std::to_string(p.privileged_dim()) + " privileged inputs)").c_str()
                                     : "",
              p.obs_norm ? "yes" : "no", o.config.empty() ? "" : "; fits the config");
  return 0;
}

int check_checkpoint(const CheckOptions& o) {
  if (o.config.empty())
    throw InputError("checkpoint " + o.file + ": --config is required to check a checkpoint (the run's config.toml)");
  const run::Checkpoint c = run::load_fitting_checkpoint(o.file, run::read_run_config(o.config), o.config);
  std::printf("%s: checkpoint at t = %lld, iteration %d, %zu logs; fits the config\n", o.file.c_str(),
              static_cast<long long>(c.loop.t), c.loop.k, c.logs.size());
  return 0;
}

int run_check(const CheckOptions& o) {
  std::ifstream in(o.file, std::ios::binary);
  if (!in) throw InputError(o.file + ": cannot open");
  char head[11] = {};
  in.read(head, sizeof head);
  if (std::memcmp(head, "CDSPOLCY", 8) == 0) return check_policy(o);
  if (std::memcmp(head, "CDSCKPT1", 8) == 0) return check_checkpoint(o);
  if (std::memcmp(head, "$MeshFormat", 11) == 0 || o.file.ends_with(".msh")) return check_mesh(o);
  throw InputError(o.file + ": not a file codesign reads; allowed: a gmsh .msh 4.1 mesh, a policy file "
                   "(policy.bin) or a checkpoint (checkpoint.bin)");
}

}  // namespace

void add_check_command(CLI::App& root, Runner& run) {
  auto opt = std::make_shared<CheckOptions>();
  CLI::App* cmd = root.add_subcommand(
      "check", "Validate a mesh (.msh 4.1), policy file or checkpoint and print what it holds; writes nothing");
  cmd->add_option("file", opt->file, "the file to check")->required();
  cmd->add_option("--config", opt->config,
                  "run config the file must fit (policy: network and observation sizes; checkpoint: required)");
  cmd->callback([opt, &run] { run = [opt] { return run_check(*opt); }; });
}

}  // namespace codesign::app
