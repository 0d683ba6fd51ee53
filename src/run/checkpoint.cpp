#include "run/checkpoint.hpp"

#include <cstring>
#include <fstream>
#include <iterator>
#include <span>

#include "base/errors.hpp"
#include "io/formats/atomic_file.hpp"
#include "rl/policy_file.hpp"
#include "run/run_folder.hpp"

namespace codesign::run {

using namespace core;  // this file works on the co-design core's types (src/core)

namespace {

constexpr char kMagic[8] = {'C', 'D', 'S', 'C', 'K', 'P', 'T', '1'};

class Writer {
 public:
  template <class T>
  void pod(const T& v) {
    const auto* p = reinterpret_cast<const unsigned char*>(&v);
    bytes.insert(bytes.end(), p, p + sizeof(T));
  }
  void floats(const Eigen::VectorXf& v) {
    pod<std::uint64_t>(static_cast<std::uint64_t>(v.size()));
    if (v.size() == 0) return;
    const auto* p = reinterpret_cast<const unsigned char*>(v.data());
    bytes.insert(bytes.end(), p, p + sizeof(float) * static_cast<std::size_t>(v.size()));
  }
  void doubles(const double* d, std::size_t n) {
    pod<std::uint64_t>(n);
    if (n == 0) return;
    const auto* p = reinterpret_cast<const unsigned char*>(d);
    bytes.insert(bytes.end(), p, p + sizeof(double) * n);
  }
  void text(const std::string& s) {
    pod<std::uint64_t>(s.size());
    bytes.insert(bytes.end(), s.begin(), s.end());
  }
  std::vector<unsigned char> bytes;
};

class Reader {
 public:
  Reader(const std::string& file, std::span<const unsigned char> b) : file_(file), b_(b) {}
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError("checkpoint " + file_ + ": " + what);
  }
  template <class T>
  T pod(const char* what) {
    if (b_.size() - pos_ < sizeof(T)) fail(std::string("truncated while reading ") + what);
    T v;
    std::memcpy(&v, b_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::uint64_t count(const char* what, std::size_t elem) {
    const auto n = pod<std::uint64_t>(what);
    if (n > (b_.size() - pos_) / elem) fail(std::string("length of ") + what + " exceeds the file");
    return n;
  }
  Eigen::VectorXf floats(const char* what) {
    const auto n = count(what, sizeof(float));
    Eigen::VectorXf v(static_cast<Eigen::Index>(n));
    if (n > 0) std::memcpy(v.data(), b_.data() + pos_, n * sizeof(float));  // (empty: data() may be null)
    pos_ += n * sizeof(float);
    if (!v.allFinite()) fail(std::string("non-finite value in ") + what);
    return v;
  }
  std::vector<double> doubles(const char* what) {
    const auto n = count(what, sizeof(double));
    std::vector<double> v(n);
    if (n > 0) std::memcpy(v.data(), b_.data() + pos_, n * sizeof(double));  // (empty: data() may be null)
    pos_ += n * sizeof(double);
    return v;
  }
  std::string text(const char* what) {
    const auto n = count(what, 1);
    std::string s(reinterpret_cast<const char*>(b_.data() + pos_), n);
    pos_ += n;
    return s;
  }
  std::size_t left() const { return b_.size() - pos_; }

 private:
  std::string file_;
  std::span<const unsigned char> b_;
  std::size_t pos_ = 0;
};

}  // namespace

std::vector<KeptCheckpoint> kept_checkpoints(const CodesignConfig& c) {
  return {{c.distribution.exploration_end, "t1", run_file::kCheckpointT1},
          {c.distribution.exploitation_start, "t2", run_file::kCheckpointT2}};
}

std::uint64_t fingerprint(const std::string& text) {
  return rl::fnv1a64(std::span<const unsigned char>(reinterpret_cast<const unsigned char*>(text.data()), text.size()));
}

void save_checkpoint(const std::string& path, const Checkpoint& c) {
  Writer w;
  w.bytes.reserve(1 << 16);
  for (const char ch : kMagic) w.pod<char>(ch);
  // Version 2 only where it adds something (observation statistics): a run without them writes
  // the version-1 bytes it always did.
  // Version 3 only for a recurrent policy, whose GRU parameters no earlier version holds.
  const bool with_obs_stats = c.loop.obs_mean.size() > 0;
  const bool recurrent = c.loop.actor_gru.size() > 0;
  w.pod<std::uint32_t>(recurrent ? 3u : with_obs_stats ? 2u : 1u);
  w.pod<std::uint64_t>(c.config_fingerprint);
  const LoopState& s = c.loop;
  w.pod<std::int64_t>(s.k);
  w.pod<std::int64_t>(s.t);
  w.pod<double>(c.wall_s);
  w.floats(s.actor);
  w.floats(s.critic);
  w.floats(s.log_std);
  w.pod<std::int64_t>(s.adam_steps);
  w.pod<std::uint64_t>(s.adam_m.size());
  for (std::size_t i = 0; i < s.adam_m.size(); ++i) {
    w.floats(s.adam_m[i]);
    w.floats(s.adam_v[i]);
  }
  w.text(s.rng_act);
  w.text(s.rng_update);
  w.text(s.rng_design);
  const DistributionState& d = s.distribution;
  const std::size_t nd = static_cast<std::size_t>(d.score.size());
  w.pod<std::uint64_t>(nd);
  w.doubles(d.score.data(), nd);
  w.doubles(d.baseline.data(), nd);
  for (std::size_t j = 0; j < nd; ++j) {
    w.doubles(d.mu[j].data(), 2);
    w.doubles(d.sigma[j].data(), 4);
    w.doubles(d.buffer[j].data(), d.buffer[j].size());
    w.pod<std::int64_t>(d.samples[j]);
  }
  w.pod<std::uint8_t>(d.collapsed ? 1 : 0);
  w.pod<std::int32_t>(d.best_design);
  w.doubles(d.best_latent.data(), 2);
  if (recurrent) w.pod<std::uint8_t>(with_obs_stats ? 1 : 0);
  if (with_obs_stats) {
    w.doubles(s.obs_mean.data(), static_cast<std::size_t>(s.obs_mean.size()));
    w.doubles(s.obs_var.data(), static_cast<std::size_t>(s.obs_var.size()));
    w.pod<double>(s.obs_count);
  }
  if (recurrent) {
    w.floats(s.actor_gru);
    w.floats(s.critic_gru);
  }
  w.pod<std::uint64_t>(c.logs.size());
  for (const auto& [name, offset] : c.logs) {
    w.text(name);
    w.pod<std::uint64_t>(offset);
  }
  w.pod<std::uint64_t>(rl::fnv1a64(w.bytes));
  io::write_file_atomically(
      path, [&](std::ostream& out) { out.write(reinterpret_cast<const char*>(w.bytes.data()), static_cast<std::streamsize>(w.bytes.size())); },
      /*binary=*/true);
}

Checkpoint load_checkpoint(const std::string& path, std::uint64_t expected_fingerprint) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("checkpoint " + path + ": cannot open");
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return parse_checkpoint(bytes, path, expected_fingerprint);
}

Checkpoint parse_checkpoint(std::span<const unsigned char> bytes, const std::string& path,
                            std::uint64_t expected_fingerprint) {
  if (bytes.size() < 8 + 4 + 8 + 8)
    throw InputError("checkpoint " + path + ": too short (" + std::to_string(bytes.size()) + " bytes)");
  if (std::memcmp(bytes.data(), kMagic, 8) != 0)
    throw InputError("checkpoint " + path + ": bad magic (not a codesign checkpoint)");
  std::uint64_t stored_sum;
  std::memcpy(&stored_sum, bytes.data() + bytes.size() - 8, 8);
  if (rl::fnv1a64(bytes.first(bytes.size() - 8)) != stored_sum)
    throw InputError("checkpoint " + path + ": checksum mismatch (file damaged or truncated)");
  Reader r(path, bytes.subspan(8, bytes.size() - 16));
  const auto version = r.pod<std::uint32_t>("version");
  if (version < 1 || version > kCheckpointVersion)
    r.fail("unsupported version " + std::to_string(version) + " (this build reads versions 1 to " +
           std::to_string(kCheckpointVersion) + ")");
  Checkpoint c;
  c.config_fingerprint = r.pod<std::uint64_t>("config fingerprint");
  if (c.config_fingerprint != expected_fingerprint)
    r.fail("written by a run with another config; resume with the run's own config.toml, or start a new run");
  LoopState& s = c.loop;
  s.k = static_cast<int>(r.pod<std::int64_t>("k"));
  s.t = r.pod<std::int64_t>("t");
  c.wall_s = r.pod<double>("wall_s");
  s.actor = r.floats("actor parameters");
  s.critic = r.floats("critic parameters");
  s.log_std = r.floats("log_std");
  s.adam_steps = r.pod<std::int64_t>("optimiser step count");
  const auto blocks = r.count("optimiser blocks", 16);
  for (std::uint64_t i = 0; i < blocks; ++i) {
    s.adam_m.push_back(r.floats("optimiser first moment"));
    s.adam_v.push_back(r.floats("optimiser second moment"));
  }
  s.rng_act = r.text("action RNG");
  s.rng_update = r.text("update RNG");
  s.rng_design = r.text("design RNG");
  DistributionState& d = s.distribution;
  const auto nd = r.count("design count", 8);
  auto fixed = [&](const char* what, std::size_t n) {
    std::vector<double> v = r.doubles(what);
    if (v.size() != n) r.fail(std::string(what) + " has " + std::to_string(v.size()) + " values, expected " + std::to_string(n));
    return v;
  };
  const std::vector<double> score = fixed("scores", nd), base = fixed("baselines", nd);
  d.score = Eigen::Map<const Eigen::VectorXd>(score.data(), static_cast<Eigen::Index>(nd));
  d.baseline = Eigen::Map<const Eigen::VectorXd>(base.data(), static_cast<Eigen::Index>(nd));
  for (std::uint64_t j = 0; j < nd; ++j) {
    const std::vector<double> mu = fixed("mu", 2), sig = fixed("sigma", 4);
    d.mu.emplace_back(mu[0], mu[1]);
    d.sigma.push_back(Eigen::Map<const Eigen::Matrix2d>(sig.data()));
    d.buffer.push_back(r.doubles("reward buffer"));
    d.samples.push_back(r.pod<std::int64_t>("sample count"));
  }
  d.collapsed = r.pod<std::uint8_t>("collapsed flag") != 0;
  d.best_design = r.pod<std::int32_t>("best design");
  const std::vector<double> bl = fixed("best latent", 2);
  d.best_latent = {bl[0], bl[1]};
  bool obs_stats = version == 2;
  if (version == 3) {
    const auto flag = r.pod<std::uint8_t>("observation statistics flag");
    if (flag > 1) r.fail("observation statistics flag " + std::to_string(flag) + " is not 0 or 1");
    obs_stats = flag == 1;
  }
  if (obs_stats) {
    const std::vector<double> mean = r.doubles("observation mean"), var = r.doubles("observation variance");
    if (mean.empty() || var.size() != mean.size())
      r.fail("observation statistics of " + std::to_string(mean.size()) + " and " + std::to_string(var.size()) +
             " components");
    s.obs_mean = Eigen::Map<const Eigen::VectorXd>(mean.data(), static_cast<Eigen::Index>(mean.size()));
    s.obs_var = Eigen::Map<const Eigen::VectorXd>(var.data(), static_cast<Eigen::Index>(var.size()));
    s.obs_count = r.pod<double>("observation count");
  }
  if (version == 3) {
    s.actor_gru = r.floats("actor GRU parameters");
    s.critic_gru = r.floats("critic GRU parameters");
    if (s.actor_gru.size() == 0 || s.critic_gru.size() == 0) r.fail("a version-3 checkpoint without GRU parameters");
  }
  const auto logs = r.count("log count", 16);
  for (std::uint64_t i = 0; i < logs; ++i) {
    std::string name = r.text("log name");
    c.logs[name] = r.pod<std::uint64_t>("log offset");
  }
  if (r.left() != 0) r.fail(std::to_string(r.left()) + " unexpected bytes after the last field");
  return c;
}

}  // namespace codesign::run
