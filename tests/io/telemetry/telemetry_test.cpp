// Telemetry over LCM. Only in-process (memq://) and log-file (file://) URLs: never multicast.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "io/telemetry/telemetry.hpp"

using namespace codesign;
namespace fs = std::filesystem;

namespace {

codesign_lcm::sim_step_t sim_step(int k) {
  codesign_lcm::sim_step_t m{};
  m.timestep = 1000000007LL + k;
  m.t_s = 0.25 * k;
  m.theta_rad = -0.125 + k;
  m.force_mN = 12.5 + k;
  m.strain = 1e-3 * (k + 1);
  m.tip_mm[0] = 1.5;
  m.tip_mm[1] = -2.5 - k;
  m.tip_mm[2] = 84.0 + k;
  m.plate_z_mm = 80.25;
  m.design = 21 + k;
  m.pressures_kPa[0] = 30.5;
  m.pressures_kPa[1] = 0.0 + k;
  m.decision = 17 + k;
  m.action = -0.75;
  return m;
}

codesign_lcm::episode_t episode(int k) {
  codesign_lcm::episode_t m{};
  m.timestep = 24000 + k;
  m.iteration = 3 + k;
  m.env = 5;
  m.design = 108;
  m.n_chambers = 2;
  m.l_mm = 12.5;
  m.w_mm = 3.25;
  m.pressures_kPa[0] = 41.0;
  m.pressures_kPa[1] = 22.5;
  m.phase_rad = 1.0 / 3.0;
  m.episode_return = 87.125 + k;
  m.decisions = 100;
  m.in_band = 61;
  m.first = (k % 2) == 0;
  m.reason = k == 0 ? "time_limit" : "numerical: diverged: CG did not converge";
  return m;
}

codesign_lcm::ppo_update_t ppo(int k) {
  codesign_lcm::ppo_update_t m{};
  m.iteration = 7 + k;
  m.timestep = 4096LL * (k + 1);
  m.pg_loss = -0.0125;
  m.value_loss = 3.5;
  m.entropy_loss = -1.25;
  m.loss = 1.75 + k;
  m.approx_kl = 0.0078125;
  m.clip_fraction = 0.1875;
  m.explained_variance = 0.625;
  m.learning_rate = 3e-4;
  m.ent_coef = 0.01;
  m.epochs = 10;
  m.early_stopped = k == 1;
  m.grad_norm = 0.4375;
  m.collect_s = 12.0;
  m.update_s = 1.5;
  m.policy_s = 0.75;
  m.steps_per_s = 310.5;
  return m;
}

codesign_lcm::distribution_t distribution(int k) {
  codesign_lcm::distribution_t m{};
  m.iteration = 11 + k;
  m.timestep = 8192 + k;
  m.phase = k == 0 ? "explore" : "exploit";
  m.beta = 2.5;
  m.entropy = 4.0;
  m.target_entropy = 3.75;
  for (int j = 0; j < 110; ++j) m.probabilities[j] = (j + 1 + k) / 6105.0;
  m.best_design = 42;
  m.best_score = 91.5;
  m.best_mu_kPa[0] = 35.0;
  m.best_mu_kPa[1] = 20.0;
  m.best_sigma_kPa[0] = 4.5;
  m.best_sigma_kPa[1] = 2.25;
  return m;
}

void expect_equal(const codesign_lcm::sim_step_t& a, const codesign_lcm::sim_step_t& b) {
  EXPECT_EQ(a.timestep, b.timestep);
  EXPECT_EQ(a.t_s, b.t_s);
  EXPECT_EQ(a.theta_rad, b.theta_rad);
  EXPECT_EQ(a.force_mN, b.force_mN);
  EXPECT_EQ(a.strain, b.strain);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(a.tip_mm[i], b.tip_mm[i]) << i;
  EXPECT_EQ(a.plate_z_mm, b.plate_z_mm);
  EXPECT_EQ(a.design, b.design);
  for (int i = 0; i < 2; ++i) EXPECT_EQ(a.pressures_kPa[i], b.pressures_kPa[i]) << i;
  EXPECT_EQ(a.decision, b.decision);
  EXPECT_EQ(a.action, b.action);
}

void expect_equal(const codesign_lcm::episode_t& a, const codesign_lcm::episode_t& b) {
  EXPECT_EQ(a.timestep, b.timestep);
  EXPECT_EQ(a.iteration, b.iteration);
  EXPECT_EQ(a.env, b.env);
  EXPECT_EQ(a.design, b.design);
  EXPECT_EQ(a.n_chambers, b.n_chambers);
  EXPECT_EQ(a.l_mm, b.l_mm);
  EXPECT_EQ(a.w_mm, b.w_mm);
  for (int i = 0; i < 2; ++i) EXPECT_EQ(a.pressures_kPa[i], b.pressures_kPa[i]) << i;
  EXPECT_EQ(a.phase_rad, b.phase_rad);
  EXPECT_EQ(a.episode_return, b.episode_return);
  EXPECT_EQ(a.decisions, b.decisions);
  EXPECT_EQ(a.in_band, b.in_band);
  EXPECT_EQ(a.first, b.first);
  EXPECT_EQ(a.reason, b.reason);
}

void expect_equal(const codesign_lcm::ppo_update_t& a, const codesign_lcm::ppo_update_t& b) {
  EXPECT_EQ(a.iteration, b.iteration);
  EXPECT_EQ(a.timestep, b.timestep);
  EXPECT_EQ(a.pg_loss, b.pg_loss);
  EXPECT_EQ(a.value_loss, b.value_loss);
  EXPECT_EQ(a.entropy_loss, b.entropy_loss);
  EXPECT_EQ(a.loss, b.loss);
  EXPECT_EQ(a.approx_kl, b.approx_kl);
  EXPECT_EQ(a.clip_fraction, b.clip_fraction);
  EXPECT_EQ(a.explained_variance, b.explained_variance);
  EXPECT_EQ(a.learning_rate, b.learning_rate);
  EXPECT_EQ(a.ent_coef, b.ent_coef);
  EXPECT_EQ(a.epochs, b.epochs);
  EXPECT_EQ(a.early_stopped, b.early_stopped);
  EXPECT_EQ(a.grad_norm, b.grad_norm);
  EXPECT_EQ(a.collect_s, b.collect_s);
  EXPECT_EQ(a.update_s, b.update_s);
  EXPECT_EQ(a.policy_s, b.policy_s);
  EXPECT_EQ(a.steps_per_s, b.steps_per_s);
}

codesign_lcm::policy_memory_t memory(int k) {
  codesign_lcm::policy_memory_t m{};
  m.timestep = 4000 + k;
  m.decision = 7 + k;
  m.design = 35;
  m.units = 3 + k;  // variable-length arrays of two sizes
  for (int u = 0; u < m.units; ++u) {
    m.actor_h.push_back(0.25f * static_cast<float>(u) - 0.5f);
    m.critic_h.push_back(-0.125f * static_cast<float>(u + k));
  }
  m.actor_norm = 1.5;
  m.critic_norm = 0.75 + k;
  return m;
}

void expect_equal(const codesign_lcm::policy_memory_t& a, const codesign_lcm::policy_memory_t& b) {
  EXPECT_EQ(a.timestep, b.timestep);
  EXPECT_EQ(a.decision, b.decision);
  EXPECT_EQ(a.design, b.design);
  EXPECT_EQ(a.units, b.units);
  EXPECT_EQ(a.actor_h, b.actor_h);
  EXPECT_EQ(a.critic_h, b.critic_h);
  EXPECT_EQ(a.actor_norm, b.actor_norm);
  EXPECT_EQ(a.critic_norm, b.critic_norm);
}

void expect_equal(const codesign_lcm::distribution_t& a, const codesign_lcm::distribution_t& b) {
  EXPECT_EQ(a.iteration, b.iteration);
  EXPECT_EQ(a.timestep, b.timestep);
  EXPECT_EQ(a.phase, b.phase);
  EXPECT_EQ(a.beta, b.beta);
  EXPECT_EQ(a.entropy, b.entropy);
  EXPECT_EQ(a.target_entropy, b.target_entropy);
  for (int j = 0; j < 110; ++j) EXPECT_EQ(a.probabilities[j], b.probabilities[j]) << j;
  EXPECT_EQ(a.best_design, b.best_design);
  EXPECT_EQ(a.best_score, b.best_score);
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(a.best_mu_kPa[i], b.best_mu_kPa[i]) << i;
    EXPECT_EQ(a.best_sigma_kPa[i], b.best_sigma_kPa[i]) << i;
  }
}

// Collects the messages an LCM instance delivers, by channel. (liblcm's C API: its C++ wrapper's
// typed subscriptions crash under the sanitizers of the ASan+UBSan build.)
struct Collector {
  std::vector<codesign_lcm::sim_step_t> sim_steps, training_steps;
  std::vector<codesign_lcm::episode_t> episodes;
  std::vector<codesign_lcm::ppo_update_t> ppo_updates;
  std::vector<codesign_lcm::distribution_t> distributions;
  std::vector<codesign_lcm::policy_memory_t> memories;
  std::vector<std::string> channels;
  int decode_errors = 0;

  template <class Message>
  void take(const lcm_recv_buf_t* rb, std::vector<Message>& into) {
    Message m;
    const int size = static_cast<int>(rb->data_size);
    if (m.decode(rb->data, 0, size) != size) {
      ++decode_errors;
      return;
    }
    into.push_back(m);
  }
  static void on_message(const lcm_recv_buf_t* rb, const char* channel, void* self_ptr) {
    auto& self = *static_cast<Collector*>(self_ptr);
    const std::string c = channel;
    self.channels.push_back(c);
    if (c == io::kSimStepChannel) self.take(rb, self.sim_steps);
    else if (c == io::kTrainStepChannel) self.take(rb, self.training_steps);
    else if (c == io::kEpisodeChannel) self.take(rb, self.episodes);
    else if (c == io::kPpoChannel) self.take(rb, self.ppo_updates);
    else if (c == io::kDistributionChannel) self.take(rb, self.distributions);
    else if (c == io::kPolicyMemoryChannel) self.take(rb, self.memories);
    else ++self.decode_errors;
  }
};

int count_lines_containing(const std::string& text, const std::string& what) {
  std::istringstream in(text);
  int n = 0;
  for (std::string line; std::getline(in, line);)
    if (line.find(what) != std::string::npos) ++n;
  return n;
}

void publish_all(io::Telemetry& t) {
  for (int k = 0; k < 2; ++k) {
    t.publish(sim_step(k));
    t.publish(episode(k));
    t.publish(ppo(k));
    t.publish(distribution(k));
    t.publish_training(sim_step(10 + k));
    t.publish(memory(k));
  }
}

const std::vector<std::string> kChannelsInOrder = {
    io::kSimStepChannel, io::kEpisodeChannel,   io::kPpoChannel,      io::kDistributionChannel,
    io::kTrainStepChannel, io::kPolicyMemoryChannel, io::kSimStepChannel, io::kEpisodeChannel,
    io::kPpoChannel,     io::kDistributionChannel, io::kTrainStepChannel, io::kPolicyMemoryChannel};

}  // namespace

TEST(Telemetry, ChannelNames) {
  EXPECT_STREQ(io::kSimStepChannel, "CODESIGN_SIM_STEP");
  EXPECT_STREQ(io::kEpisodeChannel, "CODESIGN_EPISODE");
  EXPECT_STREQ(io::kPpoChannel, "CODESIGN_PPO");
  EXPECT_STREQ(io::kDistributionChannel, "CODESIGN_DISTRIBUTION");
  EXPECT_STREQ(io::kTrainStepChannel, "CODESIGN_TRAIN_STEP");
  EXPECT_STREQ(io::kPolicyMemoryChannel, "CODESIGN_POLICY_MEMORY");
}

TEST(Telemetry, MemqRoundTripEveryField) {
  io::LcmTelemetry t("memq://");
  ASSERT_TRUE(t.enabled());
  lcm_t* l = t.connection();
  ASSERT_NE(l, nullptr);
  Collector c;
  lcm_subscribe(l, "CODESIGN_.*", &Collector::on_message, &c);

  publish_all(t);
  for (std::size_t i = 0; i < kChannelsInOrder.size(); ++i) ASSERT_EQ(lcm_handle_timeout(l, 1000), 1) << i;
  EXPECT_EQ(lcm_handle_timeout(l, 0), 0);  // nothing else queued

  EXPECT_EQ(c.decode_errors, 0);
  EXPECT_EQ(c.channels, kChannelsInOrder);
  ASSERT_EQ(c.sim_steps.size(), 2u);
  ASSERT_EQ(c.episodes.size(), 2u);
  ASSERT_EQ(c.ppo_updates.size(), 2u);
  ASSERT_EQ(c.distributions.size(), 2u);
  ASSERT_EQ(c.training_steps.size(), 2u);
  ASSERT_EQ(c.memories.size(), 2u);
  for (int k = 0; k < 2; ++k) {
    SCOPED_TRACE(k);
    expect_equal(c.sim_steps[k], sim_step(k));
    expect_equal(c.training_steps[k], sim_step(10 + k));
    expect_equal(c.episodes[k], episode(k));
    expect_equal(c.ppo_updates[k], ppo(k));
    expect_equal(c.distributions[k], distribution(k));
    expect_equal(c.memories[k], memory(k));
  }
}

TEST(Telemetry, MessagesCarryTheirFingerprint) {
  // A message of one type does not decode as another (the hash in front differs), so lcm-spy
  // and the subscribers tell the four channels' types apart.
  const auto m = episode(0);
  std::vector<unsigned char> buf(m.getEncodedSize());
  ASSERT_EQ(m.encode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
  codesign_lcm::episode_t back;
  EXPECT_EQ(back.decode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
  codesign_lcm::ppo_update_t wrong;
  EXPECT_LT(wrong.decode(buf.data(), 0, static_cast<int>(buf.size())), 0);
}

TEST(Telemetry, BadUrlWarnsOnceAndBehavesAsNull) {
  testing::internal::CaptureStderr();
  bool threw = false;
  std::unique_ptr<io::Telemetry> t;
  try {
    t = io::make_telemetry("nosuchprovider://127.0.0.1:1");
    publish_all(*t);
    publish_all(*t);
  } catch (...) {
    threw = true;
  }
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_FALSE(threw);
  ASSERT_NE(t, nullptr);
  EXPECT_FALSE(t->enabled());
  EXPECT_EQ(count_lines_containing(err, "codesign: warning: telemetry:"), 1) << err;
  EXPECT_EQ(count_lines_containing(err, "nosuchprovider://127.0.0.1:1"), 1) << err;
}

TEST(Telemetry, UnwritableLogFileWarnsOnce) {
  testing::internal::CaptureStderr();
  io::LcmTelemetry t("file:///nonexistent-dir-codesign/x/log.lcm?mode=w");
  publish_all(t);
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_FALSE(t.enabled());
  EXPECT_EQ(t.connection(), nullptr);
  EXPECT_EQ(count_lines_containing(err, "codesign: warning: telemetry:"), 1) << err;
}

TEST(Telemetry, NullAndRecording) {
  EXPECT_FALSE(io::make_telemetry("")->enabled());
  io::NullTelemetry null;
  publish_all(null);  // does nothing
  EXPECT_FALSE(null.enabled());

  io::RecordingTelemetry rec;
  EXPECT_TRUE(rec.enabled());
  publish_all(rec);
  EXPECT_EQ(rec.channels(), kChannelsInOrder);
  ASSERT_EQ(rec.sim_steps().size(), 2u);
  ASSERT_EQ(rec.episodes().size(), 2u);
  ASSERT_EQ(rec.ppo_updates().size(), 2u);
  ASSERT_EQ(rec.distributions().size(), 2u);
  ASSERT_EQ(rec.training_steps().size(), 2u);
  ASSERT_EQ(rec.policy_memories().size(), 2u);
  expect_equal(rec.sim_steps()[1], sim_step(1));
  expect_equal(rec.training_steps()[1], sim_step(11));
  expect_equal(rec.episodes()[1], episode(1));
  expect_equal(rec.ppo_updates()[1], ppo(1));
  expect_equal(rec.distributions()[1], distribution(1));
  expect_equal(rec.policy_memories()[1], memory(1));
}

TEST(Telemetry, LogFileDecodedByTheJavaTypesJar) {
#ifndef CODESIGN_DECODE_LOG_CP
  GTEST_SKIP() << "built without java/javac: codesign_lcm_types.jar and DecodeLog were not built";
#else
  const fs::path dir = fs::path(testing::TempDir()) / ("codesign_telemetry_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path log = dir / "log.lcm";
  {
    io::LcmTelemetry t("file://" + log.string() + "?mode=w");
    ASSERT_TRUE(t.enabled());
    publish_all(t);
    t.publish(sim_step(2));  // three sim steps: counts differ per channel
  }  // closes the log
  ASSERT_TRUE(fs::exists(log));

  const std::string java = CODESIGN_JAVA;
  if (std::system((java + " -version >/dev/null 2>&1").c_str()) != 0) GTEST_SKIP() << "no java";
  const std::string cmd = java + " -cp '" CODESIGN_DECODE_LOG_CP "' DecodeLog '" + log.string() + "' 2>&1";
  FILE* p = ::popen(cmd.c_str(), "r");
  ASSERT_NE(p, nullptr);
  std::string out;
  std::array<char, 512> chunk;
  while (std::fgets(chunk.data(), chunk.size(), p)) out += chunk.data();
  const int status = ::pclose(p);
  EXPECT_EQ(status, 0) << out;

  std::map<std::string, std::pair<long long, long long>> decoded;  // channel -> count, timestep sum
  long long failures = -1;
  std::istringstream in(out);
  for (std::string line; std::getline(in, line);) {
    std::istringstream l(line);
    std::string name;
    long long a = 0, b = 0;
    l >> name >> a;
    if (name == "failures") {
      failures = a;
    } else if (l >> b) {
      decoded[name] = {a, b};
    }
  }
  EXPECT_EQ(failures, 0) << out;
  ASSERT_EQ(decoded.size(), 6u) << out;
  auto sum = [](auto make, int n) {
    long long s = 0;
    for (int k = 0; k < n; ++k) s += make(k).timestep;
    return s;
  };
  EXPECT_EQ(decoded[io::kSimStepChannel], std::make_pair(3LL, sum(sim_step, 3))) << out;
  EXPECT_EQ(decoded[io::kEpisodeChannel], std::make_pair(2LL, sum(episode, 2))) << out;
  EXPECT_EQ(decoded[io::kPpoChannel], std::make_pair(2LL, sum(ppo, 2))) << out;
  EXPECT_EQ(decoded[io::kDistributionChannel], std::make_pair(2LL, sum(distribution, 2))) << out;
  EXPECT_EQ(decoded[io::kPolicyMemoryChannel], std::make_pair(2LL, sum(memory, 2))) << out;
  EXPECT_EQ(decoded[io::kTrainStepChannel],
            std::make_pair(2LL, static_cast<long long>(sim_step(10).timestep + sim_step(11).timestep)))
      << out;
  fs::remove_all(dir);
#endif
}

TEST(Telemetry, JavaDecoderRejectsAWrongType) {
  // The check above is real: an episode_t published on the PPO channel fails the fingerprint
  // check of ppo_update_t in Java.
#ifndef CODESIGN_DECODE_LOG_CP
  GTEST_SKIP() << "built without java/javac";
#else
  const std::string java = CODESIGN_JAVA;
  if (std::system((java + " -version >/dev/null 2>&1").c_str()) != 0) GTEST_SKIP() << "no java";
  const fs::path dir = fs::path(testing::TempDir()) / ("codesign_telemetry_bad_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path log = dir / "log.lcm";
  {
    lcm_t* l = lcm_create(("file://" + log.string() + "?mode=w").c_str());
    ASSERT_NE(l, nullptr);
    const auto e = episode(0);
    std::vector<unsigned char> buf(e.getEncodedSize());
    ASSERT_EQ(e.encode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
    EXPECT_EQ(lcm_publish(l, io::kEpisodeChannel, buf.data(), static_cast<unsigned>(buf.size())), 0);
    EXPECT_EQ(lcm_publish(l, io::kPpoChannel, buf.data(), static_cast<unsigned>(buf.size())), 0);
    lcm_destroy(l);
  }
  const std::string cmd = java + " -cp '" CODESIGN_DECODE_LOG_CP "' DecodeLog '" + log.string() + "' 2>&1";
  FILE* p = ::popen(cmd.c_str(), "r");
  ASSERT_NE(p, nullptr);
  std::string out;
  std::array<char, 512> chunk;
  while (std::fgets(chunk.data(), chunk.size(), p)) out += chunk.data();
  const int status = ::pclose(p);
  EXPECT_NE(status, 0) << out;
  EXPECT_EQ(count_lines_containing(out, "failures 1"), 1) << out;
  EXPECT_EQ(count_lines_containing(out, std::string(io::kEpisodeChannel) + " 1 "), 1) << out;
  fs::remove_all(dir);
#endif
}
