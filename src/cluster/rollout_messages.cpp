#include "cluster/rollout_messages.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace codesign::cluster {

std::vector<double> pack_setups(const std::vector<core::EpisodeSetup>& setups, std::size_t first, std::size_t count) {
  if (first + count > setups.size()) throw std::invalid_argument("pack_setups: slice outside the setups");
  std::vector<double> v;
  v.reserve(count * kSetupFields);
  for (std::size_t i = first; i < first + count; ++i) {
    const core::EpisodeSetup& e = setups[i];
    const core::PhysicsDraw& d = e.physics;
    v.insert(v.end(), {static_cast<double>(e.design), e.p1_kPa, e.p2_kPa, e.plate_phase_rad, e.theta0_rad,
                       static_cast<double>(static_cast<int>(e.fault)), d.youngs_scale, d.fibre_scale,
                       d.damping_scale, d.mass_scale, d.plate_amplitude_scale, d.plate_frequency_scale,
                       d.plate_height_offset_mm, d.pressure_scale_1, d.pressure_scale_2, d.strain_gain,
                       d.strain_offset, d.strain_noise, d.encoder_noise_rad, d.actuation_delay ? 1.0 : 0.0,
                       // the 64-bit noise seed in two exact 32-bit halves
                       static_cast<double>(d.noise_seed >> 32), static_cast<double>(d.noise_seed & 0xFFFFFFFFULL),
                       d.wall_offset_mm});
  }
  return v;
}

std::vector<core::EpisodeSetup> unpack_setups(const std::vector<double>& v) {
  if (v.size() % kSetupFields != 0) throw std::invalid_argument("unpack_setups: not a whole number of setups");
  const auto integer_in = [](double x, int lo, int hi, const char* what) {
    if (!(x >= lo && x <= hi) || std::floor(x) != x)
      throw std::invalid_argument(std::string("unpack_setups: ") + what + " is not an integer of its range");
    return static_cast<int>(x);
  };
  std::vector<core::EpisodeSetup> out(v.size() / kSetupFields);
  for (std::size_t i = 0; i < out.size(); ++i) {
    const double* f = &v[i * kSetupFields];
    out[i].design = integer_in(f[0], 0, 1 << 20, "a design");
    out[i].p1_kPa = f[1];
    out[i].p2_kPa = f[2];
    out[i].plate_phase_rad = f[3];
    out[i].theta0_rad = f[4];
    out[i].fault = static_cast<core::Fault>(
        integer_in(f[5], 0, static_cast<int>(core::kFaultNames.size()) - 1, "a fault"));
    core::PhysicsDraw& d = out[i].physics;
    d.youngs_scale = f[6], d.fibre_scale = f[7], d.damping_scale = f[8], d.mass_scale = f[9];
    d.plate_amplitude_scale = f[10], d.plate_frequency_scale = f[11], d.plate_height_offset_mm = f[12];
    d.pressure_scale_1 = f[13], d.pressure_scale_2 = f[14], d.strain_gain = f[15], d.strain_offset = f[16];
    d.strain_noise = f[17], d.encoder_noise_rad = f[18];
    d.actuation_delay = integer_in(f[19], 0, 1, "the actuation delay flag") == 1;
    const auto half = [&](double x) {
      if (!(x >= 0.0 && x <= 4294967295.0) || std::floor(x) != x)
        throw std::invalid_argument("unpack_setups: a noise seed half is not a 32-bit integer");
      return static_cast<std::uint64_t>(x);
    };
    d.noise_seed = half(f[20]) << 32 | half(f[21]);
    d.wall_offset_mm = f[22];
  }
  return out;
}

std::vector<double> pack_step(const rl::VecStepResult& r, const std::vector<int>& in_band) {
  const std::size_t n = static_cast<std::size_t>(r.rewards.size()), d = static_cast<std::size_t>(r.obs.rows());
  if (in_band.size() != n || r.terminal_obs.size() != n || r.terminated.size() != n || r.truncated.size() != n)
    throw std::invalid_argument("pack_step: a result whose parts differ in size");
  std::vector<double> v;
  v.reserve(n * (kStepFields + 2 * d));
  for (std::size_t i = 0; i < n; ++i) {
    const bool term = r.terminal_obs[i].has_value();
    v.insert(v.end(), {r.rewards(static_cast<Eigen::Index>(i)), static_cast<double>(r.terminated[i]),
                       static_cast<double>(r.truncated[i]), static_cast<double>(r.done(i) ? in_band[i] : 0),
                       term ? 1.0 : 0.0});
    const auto col = r.obs.col(static_cast<Eigen::Index>(i));
    v.insert(v.end(), col.data(), col.data() + d);
    if (term) {
      if (static_cast<std::size_t>(r.terminal_obs[i]->size()) != d)
        throw std::invalid_argument("pack_step: a terminal observation of another size");
      v.insert(v.end(), r.terminal_obs[i]->data(), r.terminal_obs[i]->data() + d);
    } else {
      v.insert(v.end(), d, 0.0);
    }
  }
  return v;
}

void unpack_step(const std::vector<double>& v, std::size_t obs_dim, std::size_t first, rl::VecStepResult& into,
                 std::vector<int>& last_in_band) {
  const std::size_t per = kStepFields + 2 * obs_dim;
  if (v.size() % per != 0) throw std::invalid_argument("unpack_step: not a whole number of step results");
  const std::size_t count = v.size() / per;
  if (static_cast<std::size_t>(into.obs.rows()) != obs_dim || first + count > static_cast<std::size_t>(into.obs.cols()) ||
      first + count > last_in_band.size())
    throw std::invalid_argument("unpack_step: the slice does not fit the result");
  const auto d = static_cast<Eigen::Index>(obs_dim);
  for (std::size_t k = 0; k < count; ++k) {
    const std::size_t i = first + k;
    const auto c = static_cast<Eigen::Index>(i);
    const double* f = &v[k * per];
    into.rewards(c) = f[0];
    into.terminated[i] = f[1] != 0.0 ? 1 : 0;
    into.truncated[i] = f[2] != 0.0 ? 1 : 0;
    if (into.done(i)) last_in_band[i] = static_cast<int>(f[3]);
    into.obs.col(c) = Eigen::Map<const Eigen::VectorXd>(f + kStepFields, d);
    if (f[4] != 0.0)
      into.terminal_obs[i] = Eigen::Map<const Eigen::VectorXd>(f + kStepFields + obs_dim, d);
    else
      into.terminal_obs[i].reset();
  }
}

std::string join_reasons(const std::vector<std::string>& reasons) {
  std::string s;
  for (std::size_t i = 0; i < reasons.size(); ++i) {
    if (reasons[i].find('\n') != std::string::npos) throw std::invalid_argument("join_reasons: a reason with a newline");
    if (i) s += '\n';
    s += reasons[i];
  }
  return s;
}

std::vector<std::string> split_reasons(const std::string& s, std::size_t n) {
  std::vector<std::string> out;
  std::size_t from = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t to = i + 1 < n ? s.find('\n', from) : s.size();
    if (to == std::string::npos) throw std::invalid_argument("split_reasons: fewer reasons than environments");
    out.push_back(s.substr(from, to - from));
    from = to + 1;
  }
  // The last reason runs to the end: a newline in it means more reasons than environments.
  if (n == 0 ? !s.empty() : out.back().find('\n') != std::string::npos)
    throw std::invalid_argument("split_reasons: more reasons than environments");
  return out;
}

namespace {

template <class V>
void append(std::vector<float>& out, const V& m) {
  out.insert(out.end(), m.data(), m.data() + m.size());
}

template <class V>
void take(const std::vector<float>& in, std::size_t& at, V& m) {
  std::copy(in.begin() + static_cast<std::ptrdiff_t>(at), in.begin() + static_cast<std::ptrdiff_t>(at + m.size()),
            m.data());
  at += static_cast<std::size_t>(m.size());
}

}  // namespace

PackedShare pack_share(const core::ShareRollout& share) {
  PackedShare p;
  std::vector<std::string> reasons;
  for (const core::RolloutStepColumns& s : share.steps) {
    append(p.floats, s.obs);
    append(p.floats, s.actions);
    append(p.floats, s.values);
    append(p.floats, s.log_probs);
    append(p.floats, s.rewards);
    for (std::size_t j = 0; j < s.done.size(); ++j) {
      p.doubles.push_back(s.raw_rewards(static_cast<Eigen::Index>(j)));
      p.doubles.push_back(s.done[j] ? 1.0 : 0.0);
      p.doubles.push_back(static_cast<double>(s.in_band[j]));
    }
    reasons.insert(reasons.end(), s.reasons.begin(), s.reasons.end());
  }
  append(p.floats, share.last_values);
  p.doubles.push_back(share.policy_s);
  p.reasons = join_reasons(reasons);
  return p;
}

core::ShareRollout unpack_share(const PackedShare& p, int n_steps, std::size_t n, std::size_t obs_dim,
                                std::size_t act_dim) {
  core::ShareRollout share = core::empty_share(n_steps, n, obs_dim, act_dim);
  const auto steps = static_cast<std::size_t>(n_steps);
  if (p.floats.size() != share_floats(n_steps, n, obs_dim, act_dim) || p.doubles.size() != share_doubles(n_steps, n))
    throw std::invalid_argument("unpack_share: a rollout message of " + std::to_string(p.floats.size()) + " floats and " +
                                std::to_string(p.doubles.size()) + " doubles does not fit " + std::to_string(n_steps) +
                                " decisions of " + std::to_string(n) + " environments");
  const std::vector<std::string> reasons = split_reasons(p.reasons, steps * n);
  std::size_t at = 0, d = 0;
  for (std::size_t k = 0; k < steps; ++k) {
    core::RolloutStepColumns& s = share.steps[k];
    take(p.floats, at, s.obs);
    take(p.floats, at, s.actions);
    take(p.floats, at, s.values);
    take(p.floats, at, s.log_probs);
    take(p.floats, at, s.rewards);
    for (std::size_t j = 0; j < n; ++j) {
      s.raw_rewards(static_cast<Eigen::Index>(j)) = p.doubles[d++];
      const double done = p.doubles[d++], in_band = p.doubles[d++];
      if (done != 0.0 && done != 1.0) throw std::invalid_argument("unpack_share: an end flag that is neither 0 nor 1");
      if (!(std::fabs(in_band) <= 1e9) || in_band != std::floor(in_band))
        throw std::invalid_argument("unpack_share: an in-band count that is not an integer");
      s.done[j] = done == 1.0 ? 1 : 0;
      s.in_band[j] = static_cast<int>(in_band);
      s.reasons[j] = reasons[k * n + j];
    }
  }
  take(p.floats, at, share.last_values);
  share.policy_s = p.doubles[d];
  return share;
}

std::size_t share_floats(int n_steps, std::size_t n, std::size_t obs_dim, std::size_t act_dim) {
  return static_cast<std::size_t>(n_steps) * n * (obs_dim + act_dim + 3) + n;
}

std::size_t share_doubles(int n_steps, std::size_t n) { return static_cast<std::size_t>(n_steps) * n * 3 + 1; }

std::size_t policy_size(const rl::ActorCritic& m) {
  return static_cast<std::size_t>(m.actor().params().size() + m.critic().params().size() + m.log_std().size());
}

std::vector<float> pack_policy(const rl::ActorCritic& m) {
  std::vector<float> v;
  for (const Eigen::VectorXf* p : {&m.actor().params(), &m.critic().params(), &m.log_std()})
    v.insert(v.end(), p->data(), p->data() + p->size());
  return v;
}

void unpack_policy(const std::vector<float>& v, rl::ActorCritic& m) {
  if (v.size() != policy_size(m))
    throw std::invalid_argument("unpack_policy: " + std::to_string(v.size()) + " parameters for a model of " +
                                std::to_string(policy_size(m)));
  std::size_t at = 0;
  for (Eigen::VectorXf* p : {&m.actor().params(), &m.critic().params(), &m.log_std()}) {
    *p = Eigen::Map<const Eigen::VectorXf>(v.data() + at, p->size());
    at += static_cast<std::size_t>(p->size());
  }
}

}  // namespace codesign::cluster
