#include "run/file_check.hpp"

#include <cstdio>
#include <cstring>
#include <fstream>
#include <vector>

#include "base/errors.hpp"
#include "fem/mesh_ops.hpp"
#include "io/formats/msh.hpp"
#include "rl/layer_sizes.hpp"
#include "rl/policy_file.hpp"
#include "run/checkpoint.hpp"
#include "run/file_fit.hpp"
#include "run/run_config.hpp"

namespace codesign::run {

namespace {

void check_mesh(const std::string& file) {
  const fem::TetMesh m = io::read_msh_file(file);
  check_whisker_mesh(m, file);
  double volume = 0.0;
  for (std::size_t t = 0; t < m.tets.size(); ++t) volume += fem::tet_volume(m, static_cast<int>(t));
  std::printf("%s: mesh: %zu nodes, %zu tetrahedra, volume %.6g mm^3; faces: base %zu, tip %zu", file.c_str(),
              m.nodes.size(), m.tets.size(), volume, m.base_faces.size(), m.tip_faces.size());
  for (std::size_t c = 0; c < m.chamber_faces.size(); ++c)
    std::printf(", chamber_%zu %zu", c + 1, m.chamber_faces[c].size());
  std::printf("\n");
}

void check_policy(const std::string& file, const std::string& config) {
  const rl::PolicyFileContents p = rl::load_policy(file);
  const rl::MlpT<float>& actor_mlp = p.recurrent ? p.recurrent->actor() : p.model.actor();
  const rl::MlpT<float>& critic_mlp = p.recurrent ? p.recurrent->critic() : p.model.critic();
  const std::vector<int> actor = rl::hidden_sizes(actor_mlp.sizes()), critic = rl::hidden_sizes(critic_mlp.sizes());
  if (!config.empty()) check_policy_fits(p, file, read_run_config(config), config);
  std::printf("%s: policy: obs_dim %d, act_dim %d, %sactor %s, critic %s%s, observation normalisation %s%s\n",
              file.c_str(), p.obs_dim(), p.act_dim(),
              p.recurrent ? ("GRU " + std::to_string(p.recurrent->gru_hidden()) + " before each MLP, ").c_str() : "",
              sizes_text(actor).c_str(), sizes_text(critic).c_str(),
              p.privileged_dim() > 0 ? (" (+" + std::to_string(p.privileged_dim()) + " privileged inputs)").c_str()
                                     : "",
              p.obs_norm ? "yes" : "no", config.empty() ? "" : "; fits the config");
}

void check_checkpoint(const std::string& file, const std::string& config) {
  if (config.empty())
    throw InputError("checkpoint " + file + ": --config is required to check a checkpoint (the run's config.toml)");
  const Checkpoint c = load_fitting_checkpoint(file, read_run_config(config), config);
  std::printf("%s: checkpoint at t = %lld, iteration %d, %zu logs; fits the config\n", file.c_str(),
              static_cast<long long>(c.loop.t), c.loop.k, c.logs.size());
}

}  // namespace

void check_file(const std::string& file, const std::string& config) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file + ": cannot open");
  char head[11] = {};
  in.read(head, sizeof head);
  if (std::memcmp(head, "CDSPOLCY", 8) == 0) return check_policy(file, config);
  if (std::memcmp(head, "CDSCKPT1", 8) == 0) return check_checkpoint(file, config);
  if (std::memcmp(head, "$MeshFormat", 11) == 0 || file.ends_with(".msh")) return check_mesh(file);
  throw InputError(file + ": not a file codesign reads; allowed: a gmsh .msh 4.1 mesh, a policy file "
                   "(policy.bin) or a checkpoint (checkpoint.bin)");
}

}  // namespace codesign::run
