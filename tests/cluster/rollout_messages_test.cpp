// The wire format of the MPI rollout backend: what a rank packs is what rank 0 unpacks, bit for
// bit, at the slice's place; malformed messages are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "cluster/rollout_messages.hpp"
#include "rl/rng.hpp"

namespace {

using namespace codesign;
using namespace codesign::cluster;

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(RolloutMessages, SetupsRoundTripBitForBit) {
  std::vector<core::EpisodeSetup> setups(4);
  setups[1] = {109, 19.089510258376322, 0.0, 3.14159265358979, -0.0, core::Fault::InvertedElement};
  setups[2] = {7, 1e-310, 20.0, 6.283185307179586, 0.5, core::Fault::NanPressure};
  core::RandomizeConfig randomize;
  randomize.youngs_modulus = 0.25;
  randomize.plate_height_mm = 0.3;
  randomize.strain_noise = 1e-4;
  randomize.actuation_delay = true;
  setups[2].physics = core::draw_physics(randomize, 5, 17, 3);
  setups[2].physics.wall_offset_mm = -0.25;
  ASSERT_GT(setups[2].physics.noise_seed, 0xFFFFFFFFULL);  // both halves of the seed carry bits
  const std::vector<core::EpisodeSetup> back = unpack_setups(pack_setups(setups, 1, 2));
  ASSERT_EQ(back.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    const core::EpisodeSetup &a = setups[1 + k], &b = back[k];
    EXPECT_EQ(a.design, b.design);
    EXPECT_EQ(a.fault, b.fault);
    EXPECT_EQ(a.physics, b.physics);  // every field of the draw, doubles compared exactly
    for (auto [x, y] : {std::pair{a.p1_kPa, b.p1_kPa}, {a.p2_kPa, b.p2_kPa}, {a.plate_phase_rad, b.plate_phase_rad},
                        {a.theta0_rad, b.theta0_rad}})
      EXPECT_TRUE(same_bits(x, y)) << x << " " << y;
  }
  EXPECT_THROW(pack_setups(setups, 3, 2), std::invalid_argument);
  std::vector<double> v = pack_setups(setups, 0, 1);
  v.pop_back();
  EXPECT_THROW(unpack_setups(v), std::invalid_argument);
  v = pack_setups(setups, 0, 1);
  v[5] = 3.0;  // no fault number 3
  EXPECT_THROW(unpack_setups(v), std::invalid_argument);
  v[5] = 0.0;
  v[0] = 2.5;  // not a design index
  EXPECT_THROW(unpack_setups(v), std::invalid_argument);
  v = pack_setups(setups, 0, 1);
  v[19] = 0.5;  // the delay flag is 0 or 1
  EXPECT_THROW(unpack_setups(v), std::invalid_argument);
  v[19] = 0.0;
  v[20] = 4294967296.0;  // more than 32 bits in a seed half
  EXPECT_THROW(unpack_setups(v), std::invalid_argument);
}

TEST(RolloutMessages, StepResultsLandAtTheirSliceBitForBit) {
  const std::size_t d = 3, n = 2;
  rl::VecStepResult r;
  r.obs.resize(d, n);
  r.obs << 1.0, -0.0, std::numeric_limits<double>::quiet_NaN(), 4e-320, 1e300, -7.25;
  r.rewards.resize(n);
  r.rewards << 0.73, -std::numeric_limits<double>::infinity();
  r.terminated = {0, 1};
  r.truncated = {0, 0};
  r.terminal_obs = {std::nullopt, Eigen::Vector3d(0.1, 0.2, std::numeric_limits<double>::quiet_NaN())};
  r.reasons = {"", "lost_contact"};
  const std::vector<double> packed = pack_step(r, {99, 37});

  // Rank 0's result for 5 environments; the slice goes to environments 2 and 3.
  rl::VecStepResult all;
  all.obs = Eigen::MatrixXd::Constant(d, 5, 9.0);
  all.rewards = Eigen::VectorXd::Constant(5, 9.0);
  all.terminated.assign(5, 1);
  all.truncated.assign(5, 1);
  all.terminal_obs.assign(5, Eigen::VectorXd::Constant(d, 9.0));
  all.reasons.assign(5, "x");
  std::vector<int> in_band(5, -1);
  unpack_step(packed, d, 2, all, in_band);
  for (std::size_t k = 0; k < n; ++k) {
    const auto c = static_cast<Eigen::Index>(2 + k), ck = static_cast<Eigen::Index>(k);
    EXPECT_TRUE(same_bits(all.rewards(c), r.rewards(ck)));
    for (Eigen::Index row = 0; row < static_cast<Eigen::Index>(d); ++row)
      EXPECT_TRUE(same_bits(all.obs(row, c), r.obs(row, ck))) << row << "," << k;
    EXPECT_EQ(all.terminated[2 + k], r.terminated[k]);
    EXPECT_EQ(all.truncated[2 + k], r.truncated[k]);
  }
  EXPECT_FALSE(all.terminal_obs[2].has_value());
  ASSERT_TRUE(all.terminal_obs[3].has_value());
  for (Eigen::Index row = 0; row < static_cast<Eigen::Index>(d); ++row)
    EXPECT_TRUE(same_bits((*all.terminal_obs[3])(row), (*r.terminal_obs[1])(row)));
  EXPECT_EQ(in_band[2], -1);  // no episode ended there: left as it was
  EXPECT_EQ(in_band[3], 37);
  // Outside the slice nothing changed.
  for (std::size_t i : {0u, 1u, 4u}) {
    EXPECT_EQ(all.rewards(static_cast<Eigen::Index>(i)), 9.0);
    EXPECT_EQ(in_band[i], -1);
  }
  // A slice that does not fit, or a message cut short, is refused.
  EXPECT_THROW(unpack_step(packed, d, 4, all, in_band), std::invalid_argument);
  std::vector<double> cut = packed;
  cut.pop_back();
  EXPECT_THROW(unpack_step(cut, d, 0, all, in_band), std::invalid_argument);
  EXPECT_THROW(pack_step(r, {1}), std::invalid_argument);
}

TEST(RolloutMessages, ReasonsRoundTripAndCountsAreChecked) {
  const std::vector<std::string> reasons{"", "time_limit", "", "numerical_failure"};
  EXPECT_EQ(split_reasons(join_reasons(reasons), reasons.size()), reasons);
  EXPECT_EQ(split_reasons(join_reasons({""}), 1), std::vector<std::string>{""});
  EXPECT_TRUE(split_reasons("", 0).empty());
  EXPECT_THROW(split_reasons(join_reasons(reasons), 5), std::invalid_argument);
  EXPECT_THROW(split_reasons(join_reasons(reasons), 3), std::invalid_argument);
  EXPECT_THROW(join_reasons({"a\nb"}), std::invalid_argument);
}

// Bit-for-bit equality in the matrix's own scalar type (raw_rewards are doubles: comparing them
// as floats would hide a difference below float precision). NaN payloads and -0 count.
template <class M>
bool same_bits_all(const M& a, const M& b) {
  using Scalar = typename M::Scalar;
  return a.size() == b.size() &&
         std::memcmp(a.data(), b.data(), static_cast<std::size_t>(a.size()) * sizeof(Scalar)) == 0;
}

TEST(RolloutMessages, WholeRolloutsRoundTripBitForBit) {
  const int steps = 3;
  const std::size_t n = 2, d = 4, a = 2;
  core::ShareRollout s = core::empty_share(steps, n, d, a);
  float f = 0.25f;
  for (core::RolloutStepColumns& c : s.steps) {
    for (Eigen::Index i = 0; i < c.obs.size(); ++i) c.obs(i) = f += 1.5f;
    for (Eigen::Index i = 0; i < c.actions.size(); ++i) c.actions(i) = -(f += 0.5f);
    c.values << std::numeric_limits<float>::quiet_NaN(), -0.0f;
    c.log_probs << std::numeric_limits<float>::denorm_min(), -3.5f;
    c.rewards << 1e-30f, std::numeric_limits<float>::infinity();
    c.raw_rewards << -0.0, std::numeric_limits<double>::denorm_min();
  }
  s.steps[1].done = {1, 0};
  s.steps[1].in_band = {17, 0};
  s.steps[1].reasons = {"lost_contact", ""};
  s.steps[2].done = {1, 1};
  s.steps[2].in_band = {0, 50};
  s.steps[2].reasons = {"time_limit", "time_limit"};
  s.last_values << 2.5f, -0.0f;
  s.policy_s = 0.125;
  const PackedShare p = pack_share(s);
  const core::ShareRollout t = unpack_share(p, steps, n, d, a);
  ASSERT_EQ(t.steps.size(), s.steps.size());
  for (std::size_t k = 0; k < s.steps.size(); ++k) {
    const core::RolloutStepColumns &x = s.steps[k], &y = t.steps[k];
    EXPECT_TRUE(same_bits_all(x.obs, y.obs)) << k;
    EXPECT_TRUE(same_bits_all(x.actions, y.actions)) << k;
    EXPECT_TRUE(same_bits_all(x.values, y.values)) << k;
    EXPECT_TRUE(same_bits_all(x.log_probs, y.log_probs)) << k;
    EXPECT_TRUE(same_bits_all(x.rewards, y.rewards)) << k;
    EXPECT_TRUE(same_bits_all(x.raw_rewards, y.raw_rewards)) << k;
    EXPECT_EQ(x.done, y.done) << k;
    EXPECT_EQ(x.in_band, y.in_band) << k;
    EXPECT_EQ(x.reasons, y.reasons) << k;
  }
  EXPECT_TRUE(same_bits_all(s.last_values, t.last_values));
  EXPECT_EQ(t.policy_s, 0.125);
  // Sizes, flags and counts that do not fit are refused.
  EXPECT_THROW(unpack_share(p, steps + 1, n, d, a), std::invalid_argument);
  EXPECT_THROW(unpack_share(p, steps, n, d + 1, a), std::invalid_argument);
  PackedShare bad = p;
  bad.doubles[1] = 0.5;  // the first end flag
  EXPECT_THROW(unpack_share(bad, steps, n, d, a), std::invalid_argument);
  bad = p;
  bad.doubles[2] = 2.5;  // the first in-band count
  EXPECT_THROW(unpack_share(bad, steps, n, d, a), std::invalid_argument);
  bad = p;
  bad.reasons += "\nextra";
  EXPECT_THROW(unpack_share(bad, steps, n, d, a), std::invalid_argument);
}

// The policy a rank receives for a whole rollout: every parameter of the actor, the critic and
// log_std, in that order, lands bit for bit in a model of the same shape; other sizes are refused.
TEST(RolloutMessages, PolicyParametersRoundTripBitForBit) {
  rl::ActorCritic sent(5, 2, {7, 3}, {4}, -2.0f), received(5, 2, {7, 3}, {4}, 0.0f);
  rl::Rng a(11), b(12);
  sent.init_orthogonal(a);
  received.init_orthogonal(b);  // different values everywhere, so a part left unwritten shows
  sent.log_std() << -1.25f, std::numeric_limits<float>::denorm_min();
  sent.critic().params()(0) = -0.0f;
  const std::vector<float> v = pack_policy(sent);
  // Sizes by hand: actor 5*7+7 + 7*3+3 + 3*2+2 = 74, critic 5*4+4 + 4*1+1 = 29, log_std 2.
  ASSERT_EQ(policy_size(sent), 105u);
  ASSERT_EQ(v.size(), 105u);
  ASSERT_FALSE(same_bits_all(sent.actor().params(), received.actor().params()));
  unpack_policy(v, received);
  EXPECT_TRUE(same_bits_all(sent.actor().params(), received.actor().params()));
  EXPECT_TRUE(same_bits_all(sent.critic().params(), received.critic().params()));
  EXPECT_TRUE(same_bits_all(sent.log_std(), received.log_std()));
  // The order on the wire: the actor's first, log_std's last.
  EXPECT_EQ(std::memcmp(&v.front(), sent.actor().params().data(), sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(&v.back(), &sent.log_std()(1), sizeof(float)), 0);
  rl::ActorCritic other(5, 2, {7, 4}, {4}, 0.0f);
  EXPECT_THROW(unpack_policy(v, other), std::invalid_argument);
  std::vector<float> short_v(v.begin(), v.end() - 1);
  EXPECT_THROW(unpack_policy(short_v, received), std::invalid_argument);
}

}  // namespace
