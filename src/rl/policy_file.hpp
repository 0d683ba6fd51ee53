#pragma once
// Policy files: the trained ActorCritic (sizes, weights, log_std) or RecurrentActorCritic, and
// the observation normalisation, if the trainer used one, in a versioned, checksummed binary file.
//
// Format (all integers and floats little-endian; version 1, 2 for a privileged critic, 3 for a
// recurrent policy):
//   magic     8 bytes  "CDSPOLCY"
//   version   u32      1 or 2
//   obs_dim   u32, act_dim u32
//   (version 2 only) privileged_dim u32 ≥ 1: the critic reads obs_dim + privileged_dim inputs
//   n_actor   u32, actor hidden sizes  n_actor x u32
//   n_critic  u32, critic hidden sizes n_critic x u32
//   actor params   f32 x (count implied by sizes)
//   critic params  f32 x ...
//   log_std        f32 x act_dim
//   has_norm  u32 (0/1); if 1: mean f64 x obs_dim, var f64 x obs_dim, epsilon f64, clip f64
//   checksum  u64      FNV-1a 64 of every byte before it
// Version 3 (RecurrentActorCritic, ppo.policy = "gru"): magic, version 3, obs_dim, act_dim,
//   privileged_dim u32 (0 allowed), gru_hidden u32, the hidden sizes of the actor's and the
//   critic's MLP (as above; their input is the GRU's state), then f32 parameters of the actor
//   GRU, actor MLP, critic GRU (obs_dim + privileged_dim inputs), critic MLP, log_std, and the
//   normalisation block and checksum as above.
// Writes go to "<path>.tmp" then rename() (atomic on POSIX: a reader never sees half a file).
// Any defect on load (missing file, bad magic, unknown version, truncation, trailing bytes,
// checksum mismatch, absurd sizes) throws codesign::InputError naming the file and the defect.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>

#include <Eigen/Core>

#include "rl/actor_critic.hpp"
#include "rl/recurrent_actor_critic.hpp"

namespace codesign::rl {

// The newest version this build writes and reads. Each model is written in the oldest version that
// holds it: 1 (feed-forward), 2 (feed-forward with a privileged critic), 3 (recurrent).
inline constexpr std::uint32_t kPolicyFileVersion = 3;

// SB3 VecNormalize-style observation normalisation: clip((obs - mean) / sqrt(var + eps), +-clip).
struct ObsNormalization {
  Eigen::VectorXd mean;
  Eigen::VectorXd var;
  double epsilon = 1e-8;
  double clip = 10.0;
  Eigen::VectorXd apply(const Eigen::Ref<const Eigen::VectorXd>& obs) const;
};

struct PolicyFileContents {
  ActorCritic model;  // the feed-forward policy; empty when `recurrent` holds the policy
  std::optional<ObsNormalization> obs_norm;
  std::optional<RecurrentActorCritic> recurrent = std::nullopt;  // a recurrent policy (version 3)
  int obs_dim() const { return recurrent ? recurrent->obs_dim() : model.obs_dim(); }
  int act_dim() const { return recurrent ? recurrent->act_dim() : model.act_dim(); }
  int privileged_dim() const { return recurrent ? recurrent->privileged_dim() : model.privileged_dim(); }
};

void save_policy(const std::filesystem::path& path, const ActorCritic& model,
                 const std::optional<ObsNormalization>& obs_norm = std::nullopt);
void save_policy(const std::filesystem::path& path, const RecurrentActorCritic& model,
                 const std::optional<ObsNormalization>& obs_norm = std::nullopt);
// Whichever model the contents hold.
void save_policy(const std::filesystem::path& path, const PolicyFileContents& contents);
PolicyFileContents load_policy(const std::filesystem::path& path);
// The same from the bytes of a policy file; `label` names the source in messages.
PolicyFileContents parse_policy(std::span<const unsigned char> bytes, const std::string& label);

// FNV-1a 64-bit hash (the file checksum).
std::uint64_t fnv1a64(std::span<const unsigned char> bytes);

// Inference only: load a policy file, then map raw observations (float64, as the env gives them)
// to deterministic actions (the Gaussian mean, unclipped: clip to the env's bounds yourself).
// A feed-forward policy answers act_deterministic(obs) alone; a recurrent one needs the episode's
// history, so it acts through an Episode (begin_episode()), which carries the actor's hidden
// state from one decision to the next (and also serves a feed-forward policy, statelessly).
class Policy {
 public:
  static Policy load(const std::filesystem::path& path);
  explicit Policy(PolicyFileContents contents);

  // Feed-forward policies only (throws std::logic_error for a recurrent one).
  Eigen::VectorXd act_deterministic(const Eigen::Ref<const Eigen::VectorXd>& obs) const;
  int obs_dim() const { return contents_.obs_dim(); }
  int act_dim() const { return contents_.act_dim(); }
  bool recurrent() const { return contents_.recurrent.has_value(); }
  const ActorCritic& model() const { return contents_.model; }
  const PolicyFileContents& contents() const { return contents_; }
  const std::optional<ObsNormalization>& obs_norm() const { return contents_.obs_norm; }

  // One episode of the deterministic policy: act() on the episode's observations in order. The
  // Policy must outlive it; episodes of one Policy are independent (one per thread is fine).
  class Episode {
   public:
    Eigen::VectorXd act(const Eigen::Ref<const Eigen::VectorXd>& obs);

   private:
    friend class Policy;
    explicit Episode(const Policy& policy);
    const Policy* policy_;
    Eigen::MatrixXf h_;  // the actor GRU's state (recurrent policies)
    bool first_ = true;
  };
  Episode begin_episode() const { return Episode(*this); }

 private:
  Eigen::VectorXf normalised(const Eigen::Ref<const Eigen::VectorXd>& obs) const;
  PolicyFileContents contents_;
};

}  // namespace codesign::rl
