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
#include "codesign/checkpoint.hpp"
#include "codesign/config_writer.hpp"
#include "codesign/outer_loop.hpp"
#include "codesign/run_config.hpp"
#include "codesign/whisker_env.hpp"
#include "commands.hpp"
#include "fem/mesh_ops.hpp"
#include "io/msh.hpp"
#include "rl/actor_critic.hpp"
#include "rl/policy_file.hpp"
#include "rl/recurrent_actor_critic.hpp"

namespace codesign::app {

namespace {

struct CheckOptions {
  std::string file;
  std::string config;
};

std::string sizes_text(const std::vector<int>& v) {
  std::string s = "[";
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + std::to_string(v[i]);
  return s + "]";
}

std::vector<int> hidden_of(const std::vector<int>& sizes) {
  return sizes.size() < 2 ? std::vector<int>{} : std::vector<int>(sizes.begin() + 1, sizes.end() - 1);
}

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
  const std::vector<int> actor = hidden_of(actor_mlp.sizes()), critic = hidden_of(critic_mlp.sizes());
  const std::string kind = p.recurrent ? "a recurrent policy (GRU of " + std::to_string(p.recurrent->gru_hidden()) +
                                             " units)"
                                       : std::string("a feed-forward policy");
  if (!o.config.empty()) {
    const coopt::RunConfig s = coopt::read_run_config(o.config);
    const std::string pre = "policy file " + o.file + ": ";
    const bool gru = s.ppo.policy == rl::PolicyKind::Gru;
    if (gru != p.recurrent.has_value() || (gru && p.recurrent->gru_hidden() != s.ppo.gru_hidden))
      throw InputError(pre + "holds " + kind + "; " + o.config + ": ppo.policy = " + (gru ? "\"gru\"" : "\"mlp\"") +
                       (gru ? " with ppo.gru_hidden = " + std::to_string(s.ppo.gru_hidden) : std::string()) + " needs " +
                       (gru ? "a recurrent policy of that size" : "a feed-forward policy"));
    const int obs = coopt::observation_dim(s.task);
    if (p.obs_dim() != obs)
      throw InputError(pre + "obs_dim " + std::to_string(p.obs_dim()) + " differs from " + o.config +
                       ": task.observation = \"" + coopt::to_string(s.task.observation) +
                       "\" with task.history = " + std::to_string(s.task.history) + " needs " +
                       std::to_string(obs));
    if (p.act_dim() != 1)
      throw InputError(pre + "act_dim " + std::to_string(p.act_dim()) + "; the whisker task needs 1");
    if (actor != s.ppo.actor_hidden)
      throw InputError(pre + "actor hidden sizes " + sizes_text(actor) + " differ from " + o.config +
                       ": ppo.actor_hidden = " + sizes_text(s.ppo.actor_hidden));
    const int privileged = s.ppo.privileged_critic ? coopt::kPrivilegedDim : 0;
    if (p.privileged_dim() != privileged)
      throw InputError(pre + "the critic reads " + std::to_string(p.privileged_dim()) +
                       " privileged features; " + o.config + ": ppo.privileged_critic = " +
                       (s.ppo.privileged_critic ? "true" : "false") + " needs " + std::to_string(privileged));
    if (critic != s.ppo.critic_hidden)
      throw InputError(pre + "critic hidden sizes " + sizes_text(critic) + " differ from " + o.config +
                       ": ppo.critic_hidden = " + sizes_text(s.ppo.critic_hidden));
  }
  std::printf("%s: policy: obs_dim %d, act_dim %d, %sactor %s, critic %s%s, observation normalisation %s%s\n",
              o.file.c_str(), p.obs_dim(), p.act_dim(),
              p.recurrent ? ("GRU " + std::to_string(p.recurrent->gru_hidden()) + " before each MLP, ").c_str() : "",
              sizes_text(actor).c_str(), sizes_text(critic).c_str(),
              p.privileged_dim() > 0 ? (" (+" + std::to_string(p.privileged_dim()) + " privileged inputs)").c_str()
                                     : "",
              p.obs_norm ? "yes" : "no", o.config.empty() ? "" : "; fits the config");
  return 0;
}

int check_checkpoint(const CheckOptions& o) {
  if (o.config.empty())
    throw InputError("checkpoint " + o.file + ": --config is required to check a checkpoint (the run's config.toml)");
  const coopt::RunConfig s = coopt::read_run_config(o.config);
  const coopt::LoopConfig lc{s.task, s.codesign, s.ppo};
  const std::uint64_t fp = coopt::fingerprint(coopt::resolved_run_config(s.spec, s.scene, s.solver, lc));
  const coopt::Checkpoint c = coopt::load_checkpoint(o.file, fp);
  const int obs = coopt::observation_dim(s.task), privileged = s.ppo.privileged_critic ? coopt::kPrivilegedDim : 0;
  Eigen::Index actor = 0, critic = 0, actor_gru = 0, critic_gru = 0;
  if (s.ppo.policy == rl::PolicyKind::Gru) {
    const rl::RecurrentActorCritic model(obs, 1, s.ppo.gru_hidden, s.ppo.actor_hidden, s.ppo.critic_hidden, 0.0f,
                                         privileged);
    actor = model.actor().num_params();
    critic = model.critic().num_params();
    actor_gru = model.actor_gru().num_params();
    critic_gru = model.critic_gru().num_params();
  } else {
    const rl::ActorCritic model(obs, 1, s.ppo.actor_hidden, s.ppo.critic_hidden, 0.0f, privileged);
    actor = model.actor().num_params();
    critic = model.critic().num_params();
  }
  const auto sizes = [](Eigen::Index a, Eigen::Index c, Eigen::Index ag, Eigen::Index cg) {
    return std::to_string(a) + " actor, " + std::to_string(c) + " critic" +
           (ag + cg > 0 ? ", " + std::to_string(ag) + " actor GRU, " + std::to_string(cg) + " critic GRU" : "") +
           " parameters";
  };
  if (c.loop.actor.size() != actor || c.loop.critic.size() != critic || c.loop.log_std.size() != 1 ||
      c.loop.actor_gru.size() != actor_gru || c.loop.critic_gru.size() != critic_gru)
    throw InputError("checkpoint " + o.file + ": network sizes (" +
                     sizes(c.loop.actor.size(), c.loop.critic.size(), c.loop.actor_gru.size(), c.loop.critic_gru.size()) +
                     ") differ from " + o.config + "'s (" + sizes(actor, critic, actor_gru, critic_gru) + ")");
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
