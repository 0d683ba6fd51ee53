#pragma once
// Policy files: the trained ActorCritic (sizes, weights, log_std) and the observation
// normalisation, if the trainer used one, in a versioned, checksummed binary file.
//
// Format (all integers and floats little-endian; version 1, or 2 for a privileged critic):
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

namespace codesign::rl {

// The newest version this build writes and reads (version 1, still written for a model without a
// privileged critic, is read too).
inline constexpr std::uint32_t kPolicyFileVersion = 2;

// SB3 VecNormalize-style observation normalisation: clip((obs - mean) / sqrt(var + eps), +-clip).
struct ObsNormalization {
  Eigen::VectorXd mean;
  Eigen::VectorXd var;
  double epsilon = 1e-8;
  double clip = 10.0;
  Eigen::VectorXd apply(const Eigen::Ref<const Eigen::VectorXd>& obs) const;
};

struct PolicyFileContents {
  ActorCritic model;
  std::optional<ObsNormalization> obs_norm;
};

void save_policy(const std::filesystem::path& path, const ActorCritic& model,
                 const std::optional<ObsNormalization>& obs_norm = std::nullopt);
PolicyFileContents load_policy(const std::filesystem::path& path);
// The same from the bytes of a policy file; `label` names the source in messages.
PolicyFileContents parse_policy(std::span<const unsigned char> bytes, const std::string& label);

// FNV-1a 64-bit hash (the file checksum).
std::uint64_t fnv1a64(std::span<const unsigned char> bytes);

// Inference only: load a policy file, then map raw observations (float64, as the env gives them)
// to deterministic actions (the Gaussian mean, unclipped: clip to the env's bounds yourself).
class Policy {
 public:
  static Policy load(const std::filesystem::path& path);
  explicit Policy(PolicyFileContents contents);

  Eigen::VectorXd act_deterministic(const Eigen::Ref<const Eigen::VectorXd>& obs) const;
  int obs_dim() const { return contents_.model.obs_dim(); }
  int act_dim() const { return contents_.model.act_dim(); }
  const ActorCritic& model() const { return contents_.model; }
  const std::optional<ObsNormalization>& obs_norm() const { return contents_.obs_norm; }

 private:
  PolicyFileContents contents_;
};

}  // namespace codesign::rl
