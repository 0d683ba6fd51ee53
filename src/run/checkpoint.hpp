#pragma once
// Checkpoints of a co-design run: the whole LoopState plus the run's bookkeeping, in one
// versioned, checksummed binary file written atomically (PATH.tmp, then rename).
//
// Format (little-endian; versions 1 to 3, 2 = 1 plus the observation statistics, 3 = 1 plus the
// optional statistics and the recurrent layers; each run writes the oldest version that holds its
// state):
//   magic "CDSCKPT1", u32 version, u64 config fingerprint (FNV-1a of the resolved config text),
//   i64 k, i64 t, f64 wall_s,
//   vectors (u64 length + f32 data): actor, critic, log_std,
//   i64 adam steps, u64 block count, per block: m, v,
//   strings (u64 length + bytes): act, update and design RNG states,
//   distribution: u64 designs; score, baseline (f64 vectors); per design μ (2 f64), Σ (4 f64),
//     buffer (u64 length + f64s), samples (i64); u8 collapsed, i32 best design, 2 f64 best latent,
//   version 2 only (written when ppo.normalize_observations is on): observation mean and variance
//     (u64 length + f64s each), f64 count,
//   version 3 only (written when ppo.policy = "gru"): u8 1 if the observation statistics follow
//     (as in version 2), then the actor's and the critic's GRU parameters (f32 vectors),
//   u64 log count, per log: string name, u64 byte offset,
//   u64 FNV-1a checksum of every byte before it.
// Reading checks every length against the bytes left, the checksum, the version and the config
// fingerprint, and throws codesign::InputError naming the file and the defect.
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "core/outer_loop.hpp"

namespace codesign::run {

inline constexpr std::uint32_t kCheckpointVersion = 3;

struct Checkpoint {
  std::uint64_t config_fingerprint = 0;
  double wall_s = 0.0;                         // run time before this checkpoint (progress only)
  core::LoopState loop;
  std::map<std::string, std::uint64_t> logs;   // log file name -> byte length at the checkpoint
};

void save_checkpoint(const std::string& path, const Checkpoint& c);
// expected_fingerprint: the fingerprint of the config the run is resumed with.
Checkpoint load_checkpoint(const std::string& path, std::uint64_t expected_fingerprint);
// The same from the bytes of a checkpoint file; `label` names the source in messages.
Checkpoint parse_checkpoint(std::span<const unsigned char> bytes, const std::string& label,
                            std::uint64_t expected_fingerprint);

// The checkpoints a run keeps besides checkpoint.bin: the state after the first iteration that
// reaches T1 (exploration_end) and T2 (exploitation_start), as checkpoint_t1.bin and
// checkpoint_t2.bin (`codesign evaluate --at t1|t2` reads them). A time that is not inside
// (0, total_timesteps] is never reached after an iteration and so not kept.
struct KeptCheckpoint {
  std::int64_t t = 0;
  std::string name;   // "t1" or "t2"
  std::string file;   // its file name in the run folder
};
std::vector<KeptCheckpoint> kept_checkpoints(const core::CodesignConfig& c);

// FNV-1a 64 of a text (the config fingerprint).
std::uint64_t fingerprint(const std::string& text);

}  // namespace codesign::run
