#include "rl/policy_file.hpp"

#include <cstring>
#include <filesystem>
#include <span>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "base/errors.hpp"

namespace codesign::rl {
namespace {

namespace fs = std::filesystem;

class PolicyFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("codesign_policy_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
            "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    path_ = dir_ / "policy.bin";
    Rng rng(17);
    model_ = ActorCritic(3, 2, {16, 8}, {12}, -0.5f);
    model_.init_orthogonal(rng);
    // Non-trivial head and log_std so actions are not ~0.
    model_.actor().params() *= 3.0f;
    model_.log_std() << -0.25f, 0.5f;
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::vector<char> bytes() const {
    std::ifstream in(path_, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  void write(const std::vector<char>& b) const {
    std::ofstream out(path_, std::ios::binary | std::ios::trunc);
    out.write(b.data(), static_cast<std::streamsize>(b.size()));
  }
  void expect_load_error(const std::string& fragment) const {
    try {
      load_policy(path_);
      ADD_FAILURE() << "expected InputError containing '" << fragment << "'";
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(path_.string()), std::string::npos) << msg;
      EXPECT_NE(msg.find(fragment), std::string::npos) << msg;
    }
  }

  fs::path dir_, path_;
  ActorCritic model_;
};

TEST_F(PolicyFile, RoundTripGivesBitIdenticalActions) {
  ObsNormalization norm{Eigen::Vector3d(0.1, -0.2, 0.3), Eigen::Vector3d(2.0, 0.5, 1.0), 1e-8, 5.0};
  save_policy(path_, model_, norm);
  EXPECT_FALSE(fs::exists(path_.string() + ".tmp"));
  const Policy policy = Policy::load(path_);
  EXPECT_EQ(policy.model().actor().params(), model_.actor().params());
  EXPECT_EQ(policy.model().critic().params(), model_.critic().params());
  EXPECT_EQ(policy.model().log_std(), model_.log_std());
  EXPECT_EQ(policy.model().actor().sizes(), model_.actor().sizes());
  EXPECT_EQ(policy.model().critic().sizes(), model_.critic().sizes());
  Rng rng(3);
  for (int k = 0; k < 20; ++k) {
    const Eigen::Vector3d obs(rng.normal(), rng.normal(), rng.normal());
    const Eigen::VectorXf x = norm.apply(obs).cast<float>();
    const Eigen::VectorXd expected = model_.deterministic_action(x).cast<double>();
    const Eigen::VectorXd got = policy.act_deterministic(obs);
    ASSERT_EQ(got.size(), 2);
    EXPECT_EQ(got, expected);  // bit-identical
  }
}

TEST_F(PolicyFile, RoundTripWithoutNormalisation) {
  save_policy(path_, model_);
  const PolicyFileContents c = load_policy(path_);
  EXPECT_FALSE(c.obs_norm.has_value());
  const Eigen::Vector3f obs(0.5f, -1.f, 2.f);
  EXPECT_EQ(c.model.deterministic_action(obs), model_.deterministic_action(obs));
}

TEST_F(PolicyFile, FlippedByteIsDetected) {
  save_policy(path_, model_);
  auto b = bytes();
  b[b.size() / 2] ^= 0x10;
  write(b);
  expect_load_error("checksum mismatch");
}

TEST_F(PolicyFile, TruncationIsDetected) {
  save_policy(path_, model_);
  auto b = bytes();
  b.resize(b.size() - 100);
  write(b);
  expect_load_error("checksum mismatch");
  b.resize(6);
  write(b);
  expect_load_error("too short");
}

TEST_F(PolicyFile, WrongMagicAndVersionAreDetected) {
  save_policy(path_, model_);
  auto b = bytes();
  auto wrong_version = b;
  wrong_version[8] = 7;  // version is the u32 after the 8-byte magic
  write(wrong_version);
  expect_load_error("unsupported version 7 (this build reads versions 1 to 3)");
  b[0] = 'X';
  write(b);
  expect_load_error("bad magic");
}

TEST_F(PolicyFile, MissingFileIsAnInputError) { expect_load_error("cannot open"); }

// A model without a privileged critic is written as version 1 (the files of earlier builds);
// one with a privileged critic as version 2, whose critic reads obs_dim + privileged_dim inputs.
TEST_F(PolicyFile, PrivilegedCriticRoundTripsAsVersionTwo) {
  save_policy(path_, model_);
  EXPECT_EQ(bytes()[8], 1);
  Rng rng(18);
  ActorCritic privileged(3, 2, {16, 8}, {12}, -0.5f, 5);
  privileged.init_orthogonal(rng);
  ObsNormalization norm{Eigen::Vector3d(0.1, -0.2, 0.3), Eigen::Vector3d(2.0, 0.5, 1.0), 1e-8, 5.0};
  save_policy(path_, privileged, norm);
  EXPECT_EQ(bytes()[8], 2);
  const PolicyFileContents c = load_policy(path_);
  EXPECT_EQ(c.model.obs_dim(), 3);
  EXPECT_EQ(c.model.privileged_dim(), 5);
  EXPECT_TRUE(c.model.actor().params() == privileged.actor().params());
  EXPECT_TRUE(c.model.critic().params() == privileged.critic().params());
  const Eigen::Vector3d obs(0.4, -1.0, 2.0);
  EXPECT_TRUE(Policy(c).act_deterministic(obs) == Policy(PolicyFileContents{privileged, norm}).act_deterministic(obs));
  // privileged_dim 0 in a version-2 file is a defect, named.
  auto b = bytes();
  b[20] = b[21] = b[22] = b[23] = 0;  // privileged_dim: the u32 after magic, version, obs_dim, act_dim
  // (the checksum then fails first; rewrite it so the field check is what fires)
  const std::size_t body = b.size() - 8;
  const std::uint64_t h = fnv1a64(std::span<const unsigned char>(reinterpret_cast<const unsigned char*>(b.data()), body));
  std::memcpy(b.data() + body, &h, sizeof h);
  write(b);
  expect_load_error("privileged_dim 0 out of range");
}

// A recurrent policy is written as version 3: every block bit-identical after the round trip, and
// the loaded policy's episodes act as the model's deterministic steps with a state carried from
// one decision to the next (zero at the episode's start).
TEST_F(PolicyFile, RecurrentPolicyRoundTripsAsVersionThreeAndActsWithMemory) {
  Rng rng(19);
  RecurrentActorCritic gru(3, 2, 6, {16, 8}, {12}, -0.5f, 2);
  gru.init(rng);
  gru.actor().params() *= 3.0f;
  const ObsNormalization norm{Eigen::Vector3d(0.1, -0.2, 0.3), Eigen::Vector3d(2.0, 0.5, 1.0), 1e-8, 5.0};
  save_policy(path_, PolicyFileContents{ActorCritic(), norm, gru});
  EXPECT_EQ(bytes()[8], 3);
  const PolicyFileContents c = load_policy(path_);
  ASSERT_TRUE(c.recurrent.has_value());
  EXPECT_EQ(c.obs_dim(), 3);
  EXPECT_EQ(c.act_dim(), 2);
  EXPECT_EQ(c.privileged_dim(), 2);
  EXPECT_EQ(c.recurrent->gru_hidden(), 6);
  EXPECT_TRUE(c.recurrent->actor_gru().params() == gru.actor_gru().params());
  EXPECT_TRUE(c.recurrent->actor().params() == gru.actor().params());
  EXPECT_TRUE(c.recurrent->critic_gru().params() == gru.critic_gru().params());
  EXPECT_TRUE(c.recurrent->critic().params() == gru.critic().params());
  EXPECT_TRUE(c.recurrent->log_std() == gru.log_std());
  ASSERT_TRUE(c.obs_norm.has_value());
  EXPECT_TRUE(c.obs_norm->var == norm.var);

  const Policy policy(c);
  EXPECT_TRUE(policy.recurrent());
  EXPECT_THROW(policy.act_deterministic(Eigen::Vector3d::Zero()), std::logic_error);
  Policy::Episode e1 = policy.begin_episode(), e2 = policy.begin_episode();
  Eigen::MatrixXf h = Eigen::MatrixXf::Zero(6, 1);
  Eigen::VectorXd first;
  for (int t = 0; t < 4; ++t) {
    const Eigen::Vector3d obs(0.4 * t, -1.0, 2.0 - t);
    const Eigen::VectorXd a = e1.act(obs);
    const Eigen::MatrixXf expected =
        gru.deterministic_step(norm.apply(obs).cast<float>(), Eigen::RowVectorXf::Constant(1, t == 0 ? 1.f : 0.f), h);
    EXPECT_TRUE(a == expected.col(0).cast<double>()) << "step " << t;
    if (t == 0) first = a;
  }
  // Another episode starts from zero again, whatever the first one did.
  EXPECT_TRUE(e2.act(Eigen::Vector3d(0.0, -1.0, 2.0)) == first);

  // Truncated: named.
  auto b = bytes();
  b.resize(b.size() - 40);
  const std::size_t body = b.size() - 8;
  const std::uint64_t sum = fnv1a64(std::span<const unsigned char>(reinterpret_cast<const unsigned char*>(b.data()), body));
  std::memcpy(b.data() + body, &sum, sizeof sum);
  write(b);
  expect_load_error("policy file");
}

// A feed-forward policy acts the same through an episode as through act_deterministic.
TEST_F(PolicyFile, FeedForwardEpisodeIsActDeterministic) {
  const Policy policy(PolicyFileContents{model_, std::nullopt});
  Policy::Episode e = policy.begin_episode();
  for (int t = 0; t < 3; ++t) {
    const Eigen::Vector3d obs(0.1 * t, 0.2, -0.3);
    EXPECT_TRUE(e.act(obs) == policy.act_deterministic(obs));
  }
}

}  // namespace
}  // namespace codesign::rl

namespace codesign::rl {
namespace {

// Fuzz finding (docs/journal/reliability.md, "Fuzzing campaign and findings"): 60 bytes
// declaring a network of billions of weights made the reader allocate and zero it before finding
// the weights missing. The sizes are now checked against the bytes present first.
TEST(PolicyFileSizes, HugeDeclaredNetworkIsRejectedBeforeAllocating) {
  std::vector<unsigned char> b{'C', 'D', 'S', 'P', 'O', 'L', 'C', 'Y'};
  auto u32 = [&](std::uint32_t v) {
    for (int i = 0; i < 4; ++i) b.push_back(static_cast<unsigned char>(v >> (8 * i)));
  };
  u32(1);                                   // version
  u32(1u << 20);                            // obs_dim
  u32(1);                                   // act_dim
  u32(64);                                  // actor: 64 hidden layers of 2^20
  for (int i = 0; i < 64; ++i) u32(1u << 20);
  u32(0);                                   // critic: none
  for (int i = 0; i < 8; ++i) b.push_back(0);
  const std::uint64_t sum = fnv1a64(std::span<const unsigned char>(b.data(), b.size() - 8));
  for (int i = 0; i < 8; ++i) b[b.size() - 8 + i] = static_cast<unsigned char>(sum >> (8 * i));
  // 2^20 inputs -> 64 layers of 2^20: 64 (2^40 + 2^20) + (2^20 + 1) actor, 2^20 + 1 critic, 1 log_std
  const std::uint64_t weights = 64 * ((1ull << 40) + (1ull << 20)) + ((1ull << 20) + 1) + ((1ull << 20) + 1) + 1;
  try {
    (void)parse_policy(b, "huge.bin");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("policy file huge.bin: the declared sizes (obs_dim 1048576, act_dim 1, 64 actor and 0 critic "
                     "hidden layers) need " + std::to_string(weights) + " weights; the file holds at most 0"),
              std::string::npos)
        << m;
  }
}

}  // namespace
}  // namespace codesign::rl
