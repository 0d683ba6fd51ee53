#include "rl/policy_file.hpp"

#include <bit>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <system_error>
#include <vector>

#include "base/errors.hpp"
#include "base/file_write.hpp"

namespace codesign::rl {

static_assert(std::endian::native == std::endian::little,
              "policy files are little-endian; add byte swapping for this platform");

namespace {

constexpr char kMagic[8] = {'C', 'D', 'S', 'P', 'O', 'L', 'C', 'Y'};
constexpr std::uint32_t kMaxDim = 1u << 20;
constexpr std::uint32_t kMaxLayers = 64;

class Writer {
 public:
  template <class T>
  void put(T v) {
    const auto* p = reinterpret_cast<const unsigned char*>(&v);
    bytes.insert(bytes.end(), p, p + sizeof(T));
  }
  template <class T>
  void put_array(const T* data, std::size_t n) {
    const auto* p = reinterpret_cast<const unsigned char*>(data);
    bytes.insert(bytes.end(), p, p + n * sizeof(T));
  }
  std::vector<unsigned char> bytes;
};

class Reader {
 public:
  Reader(std::span<const unsigned char> b, std::size_t end, const std::string& file)
      : bytes_(b), end_(end), file_(file) {}
  template <class T>
  T get(const char* what) {
    T v;
    get_array(&v, 1, what);
    return v;
  }
  template <class T>
  void get_array(T* out, std::size_t n, const char* what) {
    if (n > (end_ - pos_) / sizeof(T))
      throw InputError("policy file " + file_ + ": truncated while reading " + what);
    std::memcpy(out, bytes_.data() + pos_, n * sizeof(T));
    pos_ += n * sizeof(T);
  }
  std::size_t pos() const { return pos_; }
  std::size_t end() const { return end_; }

 private:
  std::span<const unsigned char> bytes_;
  std::size_t pos_ = 0;
  std::size_t end_;
  const std::string& file_;
};

void put_sizes(Writer& w, const std::vector<int>& sizes) {
  // hidden sizes only: strip input and output
  w.put<std::uint32_t>(static_cast<std::uint32_t>(sizes.size() - 2));
  for (std::size_t i = 1; i + 1 < sizes.size(); ++i) w.put<std::uint32_t>(std::uint32_t(sizes[i]));
}

std::vector<int> get_hidden(Reader& r, const std::string& file, const char* which) {
  const auto n = r.get<std::uint32_t>("layer count");
  if (n > kMaxLayers)
    throw InputError("policy file " + file + ": " + which + " has " + std::to_string(n) +
                         " hidden layers (at most " + std::to_string(kMaxLayers) + " allowed)");
  std::vector<int> hidden;
  for (std::uint32_t i = 0; i < n; ++i) {
    const auto h = r.get<std::uint32_t>("layer size");
    if (h == 0 || h > kMaxDim)
      throw InputError("policy file " + file + ": " + which + " layer size " +
                           std::to_string(h) + " out of range [1, " + std::to_string(kMaxDim) +
                           "]");
    hidden.push_back(static_cast<int>(h));
  }
  return hidden;
}

// Parameters (weights and biases) of an MLP in -> hidden... -> out; every size <= kMaxDim and at
// most kMaxLayers hidden layers, so the sum stays below 2^48.
std::uint64_t mlp_params(std::uint64_t in, const std::vector<int>& hidden, std::uint64_t out) {
  std::uint64_t n = 0, prev = in;
  for (const int h : hidden) {
    n += prev * static_cast<std::uint64_t>(h) + static_cast<std::uint64_t>(h);
    prev = static_cast<std::uint64_t>(h);
  }
  return n + prev * out + out;
}

void put_norm(Writer& w, const std::optional<ObsNormalization>& obs_norm, int obs_dim) {
  w.put<std::uint32_t>(obs_norm ? 1u : 0u);
  if (!obs_norm) return;
  if (obs_norm->mean.size() != obs_dim || obs_norm->var.size() != obs_dim)
    throw std::invalid_argument("save_policy: observation normalisation has the wrong size");
  w.put_array(obs_norm->mean.data(), static_cast<std::size_t>(obs_norm->mean.size()));
  w.put_array(obs_norm->var.data(), static_cast<std::size_t>(obs_norm->var.size()));
  w.put<double>(obs_norm->epsilon);
  w.put<double>(obs_norm->clip);
}

std::optional<ObsNormalization> get_norm(Reader& r, std::uint32_t obs_dim, const std::string& file) {
  const auto has_norm = r.get<std::uint32_t>("normalisation flag");
  if (has_norm > 1)
    throw InputError("policy file " + file + ": normalisation flag " +
                         std::to_string(has_norm) + " is not 0 or 1");
  if (has_norm == 0) return std::nullopt;
  ObsNormalization n;
  n.mean.resize(obs_dim);
  n.var.resize(obs_dim);
  r.get_array(n.mean.data(), obs_dim, "normalisation mean");
  r.get_array(n.var.data(), obs_dim, "normalisation variance");
  n.epsilon = r.get<double>("normalisation epsilon");
  n.clip = r.get<double>("normalisation clip");
  return n;
}

void finish(Writer& w, const std::filesystem::path& path) {
  w.put<std::uint64_t>(fnv1a64(w.bytes));
  write_bytes_atomically(path.string(), std::string_view(reinterpret_cast<const char*>(w.bytes.data()), w.bytes.size()));
}

// Parameters of a GRU with `in` inputs and `h` units (gru.hpp).
std::uint64_t gru_params(std::uint64_t in, std::uint64_t h) { return 3 * h * (in + h + 2); }

// The body of a version-3 file after the version (recurrent_actor_critic.hpp).
PolicyFileContents parse_recurrent(Reader& r, const std::string& file, std::uint32_t obs_dim, std::uint32_t act_dim) {
  const auto privileged_dim = r.get<std::uint32_t>("privileged_dim");
  const auto gru_hidden = r.get<std::uint32_t>("gru_hidden");
  if (privileged_dim > kMaxDim || gru_hidden == 0 || gru_hidden > kMaxDim)
    throw InputError("policy file " + file + ": privileged_dim " + std::to_string(privileged_dim) + " / gru_hidden " +
                     std::to_string(gru_hidden) + " out of range ([0, " + std::to_string(kMaxDim) + "], [1, " +
                     std::to_string(kMaxDim) + "])");
  const auto actor_hidden = get_hidden(r, file, "actor");
  const auto critic_hidden = get_hidden(r, file, "critic");
  const std::uint64_t weights = gru_params(obs_dim, gru_hidden) + mlp_params(gru_hidden, actor_hidden, act_dim) +
                                gru_params(std::uint64_t{obs_dim} + privileged_dim, gru_hidden) +
                                mlp_params(gru_hidden, critic_hidden, 1) + act_dim;
  if (weights > (r.end() - r.pos()) / sizeof(float))
    throw InputError("policy file " + file + ": the declared sizes (obs_dim " + std::to_string(obs_dim) +
                     ", act_dim " + std::to_string(act_dim) + ", gru_hidden " + std::to_string(gru_hidden) +
                     ") need " + std::to_string(weights) + " weights; the file holds at most " +
                     std::to_string((r.end() - r.pos()) / sizeof(float)));
  PolicyFileContents c;
  c.recurrent.emplace(static_cast<int>(obs_dim), static_cast<int>(act_dim), static_cast<int>(gru_hidden), actor_hidden,
                      critic_hidden, 0.0f, static_cast<int>(privileged_dim));
  RecurrentActorCritic& m = *c.recurrent;
  r.get_array(m.actor_gru().params().data(), static_cast<std::size_t>(m.actor_gru().num_params()), "actor GRU weights");
  r.get_array(m.actor().params().data(), static_cast<std::size_t>(m.actor().num_params()), "actor weights");
  r.get_array(m.critic_gru().params().data(), static_cast<std::size_t>(m.critic_gru().num_params()),
              "critic GRU weights");
  r.get_array(m.critic().params().data(), static_cast<std::size_t>(m.critic().num_params()), "critic weights");
  r.get_array(m.log_std().data(), act_dim, "log_std");
  c.obs_norm = get_norm(r, obs_dim, file);
  return c;
}

}  // namespace

std::uint64_t fnv1a64(std::span<const unsigned char> bytes) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 0x100000001b3ULL;
  }
  return h;
}

Eigen::VectorXd ObsNormalization::apply(const Eigen::Ref<const Eigen::VectorXd>& obs) const {
  return ((obs - mean).array() / (var.array() + epsilon).sqrt()).cwiseMax(-clip).cwiseMin(clip);
}

void save_policy(const std::filesystem::path& path, const ActorCritic& model,
                 const std::optional<ObsNormalization>& obs_norm) {
  Writer w;
  w.put_array(kMagic, sizeof kMagic);
  const bool privileged = model.privileged_dim() > 0;
  w.put<std::uint32_t>(privileged ? 2u : 1u);
  w.put<std::uint32_t>(static_cast<std::uint32_t>(model.obs_dim()));
  w.put<std::uint32_t>(static_cast<std::uint32_t>(model.act_dim()));
  if (privileged) w.put<std::uint32_t>(static_cast<std::uint32_t>(model.privileged_dim()));
  put_sizes(w, model.actor().sizes());
  put_sizes(w, model.critic().sizes());
  w.put_array(model.actor().params().data(), static_cast<std::size_t>(model.actor().num_params()));
  w.put_array(model.critic().params().data(),
              static_cast<std::size_t>(model.critic().num_params()));
  w.put_array(model.log_std().data(), static_cast<std::size_t>(model.log_std().size()));
  put_norm(w, obs_norm, model.obs_dim());
  finish(w, path);
}

void save_policy(const std::filesystem::path& path, const RecurrentActorCritic& model,
                 const std::optional<ObsNormalization>& obs_norm) {
  Writer w;
  w.put_array(kMagic, sizeof kMagic);
  w.put<std::uint32_t>(3u);
  w.put<std::uint32_t>(static_cast<std::uint32_t>(model.obs_dim()));
  w.put<std::uint32_t>(static_cast<std::uint32_t>(model.act_dim()));
  w.put<std::uint32_t>(static_cast<std::uint32_t>(model.privileged_dim()));
  w.put<std::uint32_t>(static_cast<std::uint32_t>(model.gru_hidden()));
  put_sizes(w, model.actor().sizes());
  put_sizes(w, model.critic().sizes());
  for (const auto* v : {&model.actor_gru().params(), &model.actor().params(), &model.critic_gru().params(),
                        &model.critic().params(), &model.log_std()})
    w.put_array(v->data(), static_cast<std::size_t>(v->size()));
  put_norm(w, obs_norm, model.obs_dim());
  finish(w, path);
}

void save_policy(const std::filesystem::path& path, const PolicyFileContents& contents) {
  if (contents.recurrent)
    save_policy(path, *contents.recurrent, contents.obs_norm);
  else
    save_policy(path, contents.model, contents.obs_norm);
}

PolicyFileContents load_policy(const std::filesystem::path& path) {
  const std::string file = path.string();
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("policy file " + file + ": cannot open");
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                         std::istreambuf_iterator<char>());
  return parse_policy(bytes, file);
}

PolicyFileContents parse_policy(std::span<const unsigned char> bytes, const std::string& file) {
  constexpr std::size_t kHeader = sizeof kMagic + sizeof(std::uint32_t);
  if (bytes.size() < kHeader + sizeof(std::uint64_t))
    throw InputError("policy file " + file + ": too short (" + std::to_string(bytes.size()) +
                         " bytes) to be a policy file");
  if (std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    throw InputError("policy file " + file + ": bad magic (not a codesign policy file)");
  std::uint32_t version;
  std::memcpy(&version, bytes.data() + sizeof kMagic, sizeof version);
  if (version < 1 || version > kPolicyFileVersion)
    throw InputError("policy file " + file + ": unsupported version " +
                         std::to_string(version) + " (this build reads versions 1 to " +
                         std::to_string(kPolicyFileVersion) + ")");
  const std::size_t body_end = bytes.size() - sizeof(std::uint64_t);
  std::uint64_t stored;
  std::memcpy(&stored, bytes.data() + body_end, sizeof stored);
  if (stored != fnv1a64(bytes.first(body_end)))
    throw InputError("policy file " + file +
                         ": checksum mismatch (file is corrupt or truncated)");

  Reader r(bytes, body_end, file);
  char magic[sizeof kMagic];
  r.get_array(magic, sizeof magic, "magic");
  (void)r.get<std::uint32_t>("version");
  const auto obs_dim = r.get<std::uint32_t>("obs_dim");
  const auto act_dim = r.get<std::uint32_t>("act_dim");
  if (obs_dim == 0 || obs_dim > kMaxDim || act_dim == 0 || act_dim > kMaxDim)
    throw InputError("policy file " + file + ": obs_dim " + std::to_string(obs_dim) +
                         " / act_dim " + std::to_string(act_dim) + " out of range [1, " +
                         std::to_string(kMaxDim) + "]");
  if (version == 3) {
    PolicyFileContents c = parse_recurrent(r, file, obs_dim, act_dim);
    if (r.pos() != r.end())
      throw InputError("policy file " + file + ": " + std::to_string(r.end() - r.pos()) +
                       " unexpected bytes after the last field");
    return c;
  }
  std::uint32_t privileged_dim = 0;
  if (version == 2) {
    privileged_dim = r.get<std::uint32_t>("privileged_dim");
    if (privileged_dim == 0 || privileged_dim > kMaxDim)
      throw InputError("policy file " + file + ": privileged_dim " + std::to_string(privileged_dim) +
                       " out of range [1, " + std::to_string(kMaxDim) + "]");
  }
  const auto actor_hidden = get_hidden(r, file, "actor");
  const auto critic_hidden = get_hidden(r, file, "critic");
  // The weights the sizes declare must be in the file before any is allocated: a few bytes
  // claiming a huge network must not make the reader fill gigabytes (fuzz finding).
  const std::uint64_t weights = mlp_params(obs_dim, actor_hidden, act_dim) +
                                mlp_params(std::uint64_t{obs_dim} + privileged_dim, critic_hidden, 1) + act_dim;
  if (weights > (r.end() - r.pos()) / sizeof(float))
    throw InputError("policy file " + file + ": the declared sizes (obs_dim " + std::to_string(obs_dim) +
                     ", act_dim " + std::to_string(act_dim) + ", " + std::to_string(actor_hidden.size()) +
                     " actor and " + std::to_string(critic_hidden.size()) + " critic hidden layers) need " +
                     std::to_string(weights) + " weights; the file holds at most " +
                     std::to_string((r.end() - r.pos()) / sizeof(float)));
  PolicyFileContents c{ActorCritic(static_cast<int>(obs_dim), static_cast<int>(act_dim),
                                   actor_hidden, critic_hidden, 0.0f, static_cast<int>(privileged_dim)),
                       std::nullopt, std::nullopt};
  r.get_array(c.model.actor().params().data(),
              static_cast<std::size_t>(c.model.actor().num_params()), "actor weights");
  r.get_array(c.model.critic().params().data(),
              static_cast<std::size_t>(c.model.critic().num_params()), "critic weights");
  r.get_array(c.model.log_std().data(), act_dim, "log_std");
  c.obs_norm = get_norm(r, obs_dim, file);
  if (r.pos() != r.end())
    throw InputError("policy file " + file + ": " + std::to_string(r.end() - r.pos()) +
                         " unexpected bytes after the last field");
  return c;
}

Policy Policy::load(const std::filesystem::path& path) { return Policy(load_policy(path)); }

Policy::Policy(PolicyFileContents contents) : contents_(std::move(contents)) {}

Eigen::VectorXf Policy::normalised(const Eigen::Ref<const Eigen::VectorXd>& obs) const {
  if (obs.size() != obs_dim())
    throw std::invalid_argument("Policy::act_deterministic: observation has " +
                                std::to_string(obs.size()) + " entries, expected " +
                                std::to_string(obs_dim()));
  return (contents_.obs_norm ? contents_.obs_norm->apply(obs) : Eigen::VectorXd(obs)).cast<float>();
}

Eigen::VectorXd Policy::act_deterministic(const Eigen::Ref<const Eigen::VectorXd>& obs) const {
  if (recurrent())
    throw std::logic_error("Policy::act_deterministic: a recurrent policy acts through begin_episode()");
  return contents_.model.deterministic_action(normalised(obs)).cast<double>();
}

Policy::Episode::Episode(const Policy& policy) : policy_(&policy) {
  if (policy.recurrent()) h_ = Eigen::MatrixXf::Zero(policy.contents_.recurrent->gru_hidden(), 1);
}

Eigen::VectorXd Policy::Episode::act(const Eigen::Ref<const Eigen::VectorXd>& obs) {
  if (!policy_->recurrent()) return policy_->act_deterministic(obs);
  const Eigen::RowVectorXf starts = Eigen::RowVectorXf::Constant(1, first_ ? 1.0f : 0.0f);
  first_ = false;
  return policy_->contents_.recurrent->deterministic_step(policy_->normalised(obs), starts, h_).col(0).cast<double>();
}

}  // namespace codesign::rl
