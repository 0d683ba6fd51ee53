#include "io/telemetry/telemetry.hpp"

#include <cstdio>

namespace codesign::io {

// The C API of liblcm: its C++ wrapper (lcm-cpp.hpp) is not needed for publishing.
LcmTelemetry::LcmTelemetry(const std::string& url) : url_(url) {
  lcm_ = lcm_create(url.empty() ? nullptr : url.c_str());
  if (lcm_) {
    enabled_ = true;
  } else {
    disable("cannot open LCM URL '" + url + "'");
  }
}

LcmTelemetry::~LcmTelemetry() {
  if (lcm_) lcm_destroy(lcm_);
}

bool LcmTelemetry::enabled() const { return enabled_.load(std::memory_order_relaxed); }

void LcmTelemetry::disable(const std::string& why) {
  enabled_ = false;
  if (lcm_) lcm_destroy(lcm_);
  lcm_ = nullptr;
  std::fprintf(stderr, "codesign: warning: telemetry: %s; telemetry is off for this run\n", why.c_str());
  std::fflush(stderr);
}

template <class Message>
void LcmTelemetry::send(const char* channel, const Message& m) {
  if (!enabled()) return;
  std::lock_guard<std::mutex> lock(mutex_);
  if (!enabled_) return;  // another thread disabled it meanwhile
  const int size = m.getEncodedSize();
  if (buffer_.size() < static_cast<std::size_t>(size)) buffer_.resize(static_cast<std::size_t>(size));
  if (m.encode(buffer_.data(), 0, size) != size) {
    disable(std::string("cannot encode a message for ") + channel);
    return;
  }
  if (lcm_publish(lcm_, channel, buffer_.data(), static_cast<unsigned int>(size)) != 0)
    disable("publishing on '" + url_ + "' failed");
}

void LcmTelemetry::publish(const codesign_lcm::sim_step_t& m) { send(kSimStepChannel, m); }
void LcmTelemetry::publish(const codesign_lcm::episode_t& m) { send(kEpisodeChannel, m); }
void LcmTelemetry::publish(const codesign_lcm::ppo_update_t& m) { send(kPpoChannel, m); }
void LcmTelemetry::publish(const codesign_lcm::distribution_t& m) { send(kDistributionChannel, m); }
void LcmTelemetry::publish(const codesign_lcm::policy_memory_t& m) { send(kPolicyMemoryChannel, m); }
void LcmTelemetry::publish_training(const codesign_lcm::sim_step_t& m) { send(kTrainStepChannel, m); }

void RecordingTelemetry::publish(const codesign_lcm::sim_step_t& m) {
  std::lock_guard<std::mutex> lock(mutex_);
  sim_steps_.push_back(m);
  channels_.emplace_back(kSimStepChannel);
}
void RecordingTelemetry::publish_training(const codesign_lcm::sim_step_t& m) {
  std::lock_guard<std::mutex> lock(mutex_);
  training_steps_.push_back(m);
  channels_.emplace_back(kTrainStepChannel);
}
void RecordingTelemetry::publish(const codesign_lcm::episode_t& m) {
  std::lock_guard<std::mutex> lock(mutex_);
  episodes_.push_back(m);
  channels_.emplace_back(kEpisodeChannel);
}
void RecordingTelemetry::publish(const codesign_lcm::ppo_update_t& m) {
  std::lock_guard<std::mutex> lock(mutex_);
  ppo_updates_.push_back(m);
  channels_.emplace_back(kPpoChannel);
}
void RecordingTelemetry::publish(const codesign_lcm::distribution_t& m) {
  std::lock_guard<std::mutex> lock(mutex_);
  distributions_.push_back(m);
  channels_.emplace_back(kDistributionChannel);
}

void RecordingTelemetry::publish(const codesign_lcm::policy_memory_t& m) {
  std::lock_guard<std::mutex> lock(mutex_);
  policy_memories_.push_back(m);
  channels_.emplace_back(kPolicyMemoryChannel);
}

std::vector<codesign_lcm::sim_step_t> RecordingTelemetry::sim_steps() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return sim_steps_;
}
std::vector<codesign_lcm::sim_step_t> RecordingTelemetry::training_steps() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return training_steps_;
}
std::vector<codesign_lcm::episode_t> RecordingTelemetry::episodes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return episodes_;
}
std::vector<codesign_lcm::ppo_update_t> RecordingTelemetry::ppo_updates() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return ppo_updates_;
}
std::vector<codesign_lcm::distribution_t> RecordingTelemetry::distributions() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return distributions_;
}
std::vector<codesign_lcm::policy_memory_t> RecordingTelemetry::policy_memories() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return policy_memories_;
}
std::vector<std::string> RecordingTelemetry::channels() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return channels_;
}

std::unique_ptr<Telemetry> make_telemetry(const std::string& url) {
  if (url.empty()) return std::make_unique<NullTelemetry>();
  return std::make_unique<LcmTelemetry>(url);
}

}  // namespace codesign::io
