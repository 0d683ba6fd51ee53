#include "run/run_logs.hpp"

#include <fstream>
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

#include "base/errors.hpp"
#include "core/failure_count.hpp"
#include "fem/design.hpp"
#include "run/run_folder.hpp"

namespace codesign::run {

namespace {

namespace fs = std::filesystem;
using io::CsvLog;

std::string num(double v) { return CsvLog::num(v); }
std::string num(std::int64_t v) { return CsvLog::num(v); }
std::string num(int v) { return CsvLog::num(static_cast<std::int64_t>(v)); }

std::vector<std::string> q_columns() {
  std::vector<std::string> c{"k", "t"};
  for (int j = 0; j < fem::kDesignCount; ++j) {
    std::string name = "q";  // (not "q" + to_string: GCC 12 reports a false -Wrestrict)
    name += std::to_string(j);
    c.push_back(std::move(name));
  }
  return c;
}

std::vector<std::string> distribution_columns(bool target_entropy) {
  std::vector<std::string> c{"k", "t", "phase", "beta", "entropy"};
  if (target_entropy) c.push_back("target_entropy");
  for (const char* name : {"top1_j", "top1_q", "top2_j", "top2_q", "top3_j", "top3_q", "best_j", "best_score",
                           "best_mu1_kPa", "best_mu2_kPa", "best_sigma1_kPa", "best_sigma2_kPa"})
    c.emplace_back(name);
  return c;
}

// The checkpointed length of a log to resume (checked against the file), or none.
std::optional<std::uint64_t> position(const fs::path& dir, const std::string& name,
                                      const std::vector<std::string>& columns,
                                      const std::map<std::string, std::uint64_t>* resume) {
  if (!resume) return std::nullopt;
  const auto it = resume->find(name);
  if (it == resume->end()) throw InputError("checkpoint: has no position for " + name);
  CsvLog::check_resumable((dir / name).string(), columns, it->second);
  return it->second;
}

std::vector<std::string> episode_columns(bool physics, bool walls) {
  std::vector<std::string> c{"t", "k", "j", "n", "l_mm", "w_mm", "p1_kPa", "p2_kPa", "phase_rad", "return",
                             "decisions", "in_band", "first"};
  if (physics)
    for (const char* name : {"E_scale", "fibre_scale", "damping_scale", "mass_scale", "plate_amplitude_scale",
                             "plate_frequency_scale", "plate_height_offset_mm", "p1_scale", "p2_scale", "strain_gain",
                             "strain_offset", "strain_noise", "encoder_noise_rad", "actuation_delay"})
      c.emplace_back(name);
  if (walls) c.emplace_back("wall_offset_mm");
  c.emplace_back("reason");  // last: numerical_failures_logged reads it there
  return c;
}

}  // namespace

RunLogs::RunLogs(const fs::path& dir, const std::map<std::string, std::uint64_t>* resume, bool target_entropy,
                 bool physics, bool walls)
    : physics_(physics), walls_(walls) {
  const std::vector<std::pair<std::string, std::vector<std::string>>> logs{
      {run_file::kEpisodes, episode_columns(physics, walls)},
      {run_file::kPpo,
       {"k", "t", "pg_loss", "value_loss", "entropy_loss", "loss", "approx_kl", "clip_fraction",
        "explained_variance", "lr", "ent_coef", "epochs", "early_stopped", "grad_norm", "collect_s", "update_s",
        "policy_s", "steps_per_s"}},
      {run_file::kDistribution, distribution_columns(target_entropy)},
      {run_file::kQDisc, q_columns()},
      {run_file::kSampled,
       {"k", "t", "i", "j", "p1_kPa", "p2_kPa", "return", "mu1_kPa", "mu2_kPa", "sigma1_kPa", "sigma2_kPa"}}};
  for (const auto& [name, columns] : logs) (void)position(dir, name, columns, resume);
  std::unique_ptr<CsvLog>* member[] = {&episodes_, &ppo_, &distribution_, &q_, &sampled_};
  for (std::size_t i = 0; i < logs.size(); ++i) {
    const auto& [name, columns] = logs[i];
    *member[i] = std::make_unique<CsvLog>((dir / name).string(), columns, position(dir, name, columns, resume));
  }
}

void RunLogs::write_iteration(const core::IterationReport& rep, const core::DesignDistribution& dist,
                              const DistributionSummary& summary, double steps_per_s) {
  for (const core::EpisodeRecord& e : rep.episodes) {
    const fem::Design d = fem::design_from_index(e.setup.design);
    std::vector<std::string> row{num(rep.t), num(rep.k), num(e.setup.design), num(d.n), num(d.chamber_length_mm),
                                 num(d.wall_mm), num(e.setup.p1_kPa), num(e.setup.p2_kPa),
                                 num(e.setup.plate_phase_rad), num(e.episode_return), num(e.decisions),
                                 num(e.in_band), num(e.first ? 1 : 0)};
    if (physics_) {
      const core::PhysicsDraw& p = e.setup.physics;
      row.insert(row.end(), {num(p.youngs_scale), num(p.fibre_scale), num(p.damping_scale), num(p.mass_scale),
                             num(p.plate_amplitude_scale), num(p.plate_frequency_scale), num(p.plate_height_offset_mm),
                             num(p.pressure_scale_1), num(p.pressure_scale_2), num(p.strain_gain),
                             num(p.strain_offset), num(p.strain_noise), num(p.encoder_noise_rad),
                             num(p.actuation_delay ? 1 : 0)});
      if (walls_) row.push_back(num(p.wall_offset_mm));
    }
    row.push_back(e.reason);
    episodes_->row(row);
  }
  const rl::PpoStats& p = rep.ppo;
  ppo_->row({num(rep.k), num(rep.t), num(p.pg_loss), num(p.value_loss), num(p.entropy_loss), num(p.loss),
             num(p.approx_kl), num(p.clip_fraction), num(p.explained_variance), num(rep.learning_rate),
             num(p.ent_coef), num(p.epochs_done), num(p.early_stopped ? 1 : 0), num(p.grad_norm), num(rep.collect_s),
             num(rep.update_s), num(rep.policy_s), num(steps_per_s)});
  const Eigen::VectorXd& q = summary.q;
  std::vector<std::string> dist_row{num(rep.k), num(rep.t), core::to_string(summary.phase), num(rep.beta),
                                    num(summary.entropy)};
  if (summary.target_entropy) dist_row.push_back(num(*summary.target_entropy));
  const std::array<int, 3>& top = summary.top;
  dist_row.insert(dist_row.end(),
                  {num(top[0]), num(q[top[0]]), num(top[1]), num(q[top[1]]), num(top[2]), num(q[top[2]]),
                   num(summary.best), num(summary.best_score), num(summary.mu[0]), num(summary.mu[1]),
                   num(summary.sigma[0]), num(summary.sigma[1])});
  distribution_->row(dist_row);
  std::vector<std::string> q_row{num(rep.k), num(rep.t)};
  for (Eigen::Index j = 0; j < q.size(); ++j) q_row.push_back(num(q[j]));
  q_->row(q_row);
  for (std::size_t i = 0; i < rep.samples.size(); ++i) {
    const core::DesignSample& s = rep.samples[i];
    const Eigen::Vector2d m = dist.mean_pressures_kPa(s.design), sd = dist.sigma_pressures_kPa(s.design);
    sampled_->row({num(rep.k), num(rep.t), num(static_cast<std::int64_t>(i)), num(s.design), num(s.pressures_kPa[0]),
                   num(s.pressures_kPa[1]), num(rep.returns[i]), num(m[0]), num(m[1]), num(sd[0]), num(sd[1])});
  }
}

std::map<std::string, std::uint64_t> RunLogs::flush() {
  return {{run_file::kEpisodes, episodes_->flush()},
          {run_file::kPpo, ppo_->flush()},
          {run_file::kDistribution, distribution_->flush()},
          {run_file::kQDisc, q_->flush()},
          {run_file::kSampled, sampled_->flush()}};
}

std::int64_t RunLogs::numerical_failures_logged(const fs::path& dir) {
  std::ifstream in(dir / run_file::kEpisodes, std::ios::binary);
  std::string line;
  std::int64_t n = 0;
  bool header = true;
  while (std::getline(in, line)) {
    if (header) {
      header = false;
      continue;
    }
    // The reason is the last column.
    const auto comma = line.rfind(',');
    if (comma != std::string::npos && core::is_numerical_failure(std::string_view(line).substr(comma + 1))) ++n;
  }
  return n;
}

}  // namespace codesign::run
