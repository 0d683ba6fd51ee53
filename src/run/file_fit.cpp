#include "run/file_fit.hpp"

#include "base/errors.hpp"
#include "core/outer_loop.hpp"
#include "core/whisker_env.hpp"
#include "rl/actor_critic.hpp"
#include "rl/layer_sizes.hpp"
#include "rl/recurrent_actor_critic.hpp"
#include "run/codesign_tables_writer.hpp"

namespace codesign::run {

using namespace core;  // this file works on the co-design core's types (src/core)

std::string sizes_text(const std::vector<int>& v) {
  std::string s = "[";
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + std::to_string(v[i]);
  return s + "]";
}

void check_policy_fits(const rl::PolicyFileContents& p, const std::string& file, const RunConfig& s,
                       const std::string& config_file) {
  const rl::MlpT<float>& actor_mlp = p.recurrent ? p.recurrent->actor() : p.model.actor();
  const rl::MlpT<float>& critic_mlp = p.recurrent ? p.recurrent->critic() : p.model.critic();
  const std::vector<int> actor = rl::hidden_sizes(actor_mlp.sizes()), critic = rl::hidden_sizes(critic_mlp.sizes());
  const std::string kind = p.recurrent ? "a recurrent policy (GRU of " + std::to_string(p.recurrent->gru_hidden()) +
                                             " units)"
                                       : std::string("a feed-forward policy");
  const std::string pre = "policy file " + file + ": ";
  const bool gru = s.ppo.policy == rl::PolicyKind::Gru;
  std::string policy_key = "\"";
  policy_key.append(name_of(rl::kPolicyKindNames, s.ppo.policy)).append("\"");
  if (gru != p.recurrent.has_value() || (gru && p.recurrent->gru_hidden() != s.ppo.gru_hidden))
    throw InputError(pre + "holds " + kind + "; " + config_file + ": ppo.policy = " + policy_key +
                     (gru ? " with ppo.gru_hidden = " + std::to_string(s.ppo.gru_hidden) : std::string()) + " needs " +
                     (gru ? "a recurrent policy of that size" : "a feed-forward policy"));
  const int obs = observation_dim(s.task);
  if (p.obs_dim() != obs)
    throw InputError(pre + "obs_dim " + std::to_string(p.obs_dim()) + " differs from " + config_file +
                     ": task.observation = \"" + to_string(s.task.observation) + "\" with task.history = " +
                     std::to_string(s.task.history) + " needs " + std::to_string(obs));
  if (p.act_dim() != 1) throw InputError(pre + "act_dim " + std::to_string(p.act_dim()) + "; the whisker task needs 1");
  if (actor != s.ppo.actor_hidden)
    throw InputError(pre + "actor hidden sizes " + sizes_text(actor) + " differ from " + config_file +
                     ": ppo.actor_hidden = " + sizes_text(s.ppo.actor_hidden));
  const int privileged = s.ppo.privileged_critic ? kPrivilegedDim : 0;
  if (p.privileged_dim() != privileged)
    throw InputError(pre + "the critic reads " + std::to_string(p.privileged_dim()) + " privileged features; " +
                     config_file + ": ppo.privileged_critic = " + (s.ppo.privileged_critic ? "true" : "false") +
                     " needs " + std::to_string(privileged));
  if (critic != s.ppo.critic_hidden)
    throw InputError(pre + "critic hidden sizes " + sizes_text(critic) + " differ from " + config_file +
                     ": ppo.critic_hidden = " + sizes_text(s.ppo.critic_hidden));
}

Checkpoint load_fitting_checkpoint(const std::string& file, const RunConfig& s, const std::string& config_file) {
  const LoopConfig lc{s.task, s.codesign, s.ppo};
  const std::uint64_t fp = fingerprint(resolved_run_config(s.spec, s.scene, s.solver, lc));
  Checkpoint c = load_checkpoint(file, fp);
  const int obs = observation_dim(s.task), privileged = s.ppo.privileged_critic ? kPrivilegedDim : 0;
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
  const auto sizes = [](Eigen::Index a, Eigen::Index cr, Eigen::Index ag, Eigen::Index cg) {
    return std::to_string(a) + " actor, " + std::to_string(cr) + " critic" +
           (ag + cg > 0 ? ", " + std::to_string(ag) + " actor GRU, " + std::to_string(cg) + " critic GRU" : "") +
           " parameters";
  };
  if (c.loop.actor.size() != actor || c.loop.critic.size() != critic || c.loop.log_std.size() != 1 ||
      c.loop.actor_gru.size() != actor_gru || c.loop.critic_gru.size() != critic_gru)
    throw InputError("checkpoint " + file + ": network sizes (" +
                     sizes(c.loop.actor.size(), c.loop.critic.size(), c.loop.actor_gru.size(), c.loop.critic_gru.size()) +
                     ") differ from " + config_file + "'s (" + sizes(actor, critic, actor_gru, critic_gru) + ")");
  return c;
}

void check_whisker_mesh(const fem::TetMesh& m, const std::string& file) {
  const char* need = "; a whisker mesh needs triangles in the physical surfaces \"base\" (clamped), \"tip\" and "
                     "\"chamber_1\" (and \"chamber_2\" for two chambers)";
  if (m.base_faces.empty()) throw InputError(file + ": physical group \"base\": no triangles" + need);
  if (m.tip_faces.empty()) throw InputError(file + ": physical group \"tip\": no triangles" + need);
  if (m.chamber_faces.empty() || m.chamber_faces[0].empty())
    throw InputError(file + ": physical group \"chamber_1\": no triangles" + need);
  if (m.chamber_faces.size() > 2)
    throw InputError(file + ": physical group \"chamber_" + std::to_string(m.chamber_faces.size()) +
                     "\": at most 2 chambers (chamber_1, chamber_2) are allowed");
}

}  // namespace codesign::run
