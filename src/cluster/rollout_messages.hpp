#pragma once
// The wire format of the MPI rollout backend (mpi_env_pool.hpp): episode setups out to a rank,
// its slice's step results back, as flat arrays of doubles (copied bit for bit: NaN payloads,
// signed zeros and denormals arrive as sent) and the end reasons as one string. No MPI here, so the
// format is tested on its own (tests/cluster/rollout_messages_test.cpp).
#include <cstddef>
#include <string>
#include <vector>

#include "core/run_ahead.hpp"
#include "core/whisker_env.hpp"
#include "rl/actor_critic.hpp"
#include "rl/vec_env.hpp"

namespace codesign::cluster {

// design, p1, p2, plate phase, theta0, fault, then the physics draw (16 numbers)
inline constexpr std::size_t kSetupFields = 23;
inline constexpr std::size_t kStepFields = 5;   // reward, terminated, truncated, in-band count, has terminal obs

// setups[first, first + count) as count · kSetupFields numbers.
std::vector<double> pack_setups(const std::vector<core::EpisodeSetup>& setups, std::size_t first, std::size_t count);
// The inverse; std::invalid_argument if the size is not a multiple of kSetupFields or a design or
// fault number is not an integer of its range.
std::vector<core::EpisodeSetup> unpack_setups(const std::vector<double>& v);

// One slice's step result: per environment kStepFields numbers, its observation and its terminal
// observation (zeros where the episode did not end). in_band[i]: the in-band decisions of the
// episode that environment i ended at this step (read only where it ended).
std::vector<double> pack_step(const rl::VecStepResult& r, const std::vector<int>& in_band);
// Writes a packed slice into environments [first, first + slice) of `into` (its obs matrix and
// vectors already sized for all environments) and of last_in_band (where an episode ended); the
// reasons are not part of it. std::invalid_argument if the size does not fit obs_dim or `into`.
void unpack_step(const std::vector<double>& v, std::size_t obs_dim, std::size_t first, rl::VecStepResult& into,
                 std::vector<int>& last_in_band);

// End reasons as one '\n'-separated string, and back (std::invalid_argument for a reason holding
// a newline, or a string with another number of reasons).
std::string join_reasons(const std::vector<std::string>& reasons);
std::vector<std::string> split_reasons(const std::string& s, std::size_t n);

// A rank's whole rollout (run_ahead.hpp) as three messages: its floats (per decision the
// observations, actions, values, log-probabilities and bootstrapped rewards; then the last values),
// its doubles (per decision and environment the raw reward, the end flag and the in-band count;
// then the policy's seconds) and the end reasons of every decision (join_reasons).
struct PackedShare {
  std::vector<float> floats;
  std::vector<double> doubles;
  std::string reasons;
};
PackedShare pack_share(const core::ShareRollout& share);
// The sizes of those messages for n_steps decisions of n environments.
std::size_t share_floats(int n_steps, std::size_t n, std::size_t obs_dim, std::size_t act_dim);
std::size_t share_doubles(int n_steps, std::size_t n);
// The inverse for n_steps decisions of n environments; std::invalid_argument if a message does not
// have the size that implies, or an end flag is neither 0 nor 1.
core::ShareRollout unpack_share(const PackedShare& p, int n_steps, std::size_t n, std::size_t obs_dim,
                                std::size_t act_dim);

// The policy's parameters as one array (the actor's, the critic's, then log σ), its size, and
// back into a model of the same shape (std::invalid_argument for another size).
std::size_t policy_size(const rl::ActorCritic& m);
std::vector<float> pack_policy(const rl::ActorCritic& m);
void unpack_policy(const std::vector<float>& v, rl::ActorCritic& m);

}  // namespace codesign::cluster
