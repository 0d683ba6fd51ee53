#include "io/config_writer.hpp"

#include <charconv>
#include <cmath>
#include <limits>
#include <numbers>

namespace codesign::io {

namespace {

std::string shortest(double v) {
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, res.ptr);
}

// An x with read(x) == stored for a nondecreasing read(), searched from `guess` in steps of
// one ulp (at most 64); of the neighbours that also map onto `stored` (64 either side) the one
// with the shortest decimal form, so a value written as 37.3 is written back as 37.3.
// `guess` itself if there is none.
template <class Read>
double preimage(double stored, double guess, Read read) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  double x = guess;
  for (int i = 0; i < 64 && std::isfinite(x) && read(x) != stored; ++i)
    x = std::nextafter(x, read(x) < stored ? inf : -inf);
  if (!std::isfinite(x) || read(x) != stored) return guess;
  double best = x;
  for (const double dir : {-inf, inf}) {
    double y = std::nextafter(x, dir);
    for (int k = 0; k < 64 && std::isfinite(y) && read(y) == stored; ++k, y = std::nextafter(y, dir))
      if (shortest(y).size() < shortest(best).size()) best = y;
  }
  return best;
}

}  // namespace

std::string toml_number(double v) {
  std::string s = shortest(v);
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";  // "500" would be an integer
  return s;
}

TomlTableWriter::TomlTableWriter(std::ostream& out, std::string_view table) : out_(out) {
  out_ << '[' << table << "]\n";
}

TomlTableWriter::~TomlTableWriter() { out_ << '\n'; }

void TomlTableWriter::number(std::string_view key, double v) { out_ << key << " = " << toml_number(v) << '\n'; }

void TomlTableWriter::integer(std::string_view key, std::int64_t v) { out_ << key << " = " << v << '\n'; }

void TomlTableWriter::boolean(std::string_view key, bool v) {
  out_ << key << " = " << (v ? "true" : "false") << '\n';
}

void TomlTableWriter::string(std::string_view key, std::string_view v) {
  out_ << key << " = \"" << v << "\"\n";
}

void TomlTableWriter::integers(std::string_view key, const std::vector<int>& v) {
  out_ << key << " = [";
  for (std::size_t i = 0; i < v.size(); ++i) out_ << (i ? ", " : "") << v[i];
  out_ << "]\n";
}

void TomlTableWriter::scaled(std::string_view key, double stored, double scale) {
  number(key, preimage(stored, stored / scale, [scale](double x) { return scale * x; }));
}

void TomlTableWriter::degrees(std::string_view key, double stored_rad) {
  // The readers' expression, evaluated in the same order: t.number(...) * pi / 180.0.
  number(key, preimage(stored_rad, stored_rad * 180.0 / std::numbers::pi,
                       [](double x) { return x * std::numbers::pi / 180.0; }));
}

void write_fem_tables(std::ostream& out, const fem::WhiskerModelSpec& spec, const fem::SceneConfig& scene,
                      const fem::SolverConfig& solver) {
  {
    const fem::Material& m = spec.model.material;
    TomlTableWriter t(out, "material");
    t.scaled("youngs_modulus_kPa", m.youngs_modulus_Pa, 1e3);
    t.number("poisson_ratio", m.poisson_ratio);
    t.number("total_mass_g", m.total_mass_g);
    t.number("gravity_mm_s2", m.gravity_mm_s2);
    t.number("rayleigh_mass_per_s", m.rayleigh_mass_per_s);
    t.number("rayleigh_stiffness_s", m.rayleigh_stiffness_s);
  }
  {
    TomlTableWriter t(out, "scene");
    t.number("inclination_deg", scene.inclination_deg);
    t.number("preload_mm", scene.preload_mm);
    t.number("plate_amplitude_mm", scene.plate_amplitude_mm);
    t.number("plate_frequency_Hz", scene.plate_frequency_Hz);
    t.degrees("plate_phase_deg", scene.plate_phase_rad);
    t.number("theta_limit_deg", scene.theta_limit_deg);
    t.integer("settle_steps", scene.settle_steps);
    t.number("tip_region_mm", spec.model.tip_region_mm);
  }
  {
    TomlTableWriter t(out, "solver");
    t.string("method", name_of(fem::kStepMethodNames, solver.method));
    t.number("dt_s", solver.dt_s);
    t.number("static_dt_s", solver.static_dt_s);
    t.number("fast_tolerance", solver.fast_tolerance);
    // Only when it is not the default, so the resolved configs (and fingerprints) of runs made
    // before the key existed stay as they were.
    if (solver.fast_stop != fem::SolverConfig{}.fast_stop)
      t.string("fast_stop", name_of(fem::kFastStopNames, solver.fast_stop));
    t.integer("fast_max_iterations", solver.fast_max_iterations);
    t.integer("fast_refactor_iterations", solver.fast_refactor_iterations);
    t.number("contact_tolerance_mm", solver.contact_tolerance_mm);
    t.number("contact_margin_mm", solver.contact_margin_mm);
  }
  {
    const fem::WhiskerGeometry& g = spec.geometry;
    TomlTableWriter t(out, "geometry");
    t.number("length_mm", g.length_mm);
    t.number("base_diameter_mm", g.base_diameter_mm);
    t.number("tip_diameter_mm", g.tip_diameter_mm);
    t.number("proximal_cap_mm", g.proximal_cap_mm);
  }
  {
    const fem::MeshOptions& o = spec.mesh;
    TomlTableWriter t(out, "mesh");
    t.number("max_size_mm", o.max_size_mm);
    t.number("radius_factor", o.radius_factor);
    t.number("wall_factor", o.wall_factor);
    t.number("grading", o.grading);
    t.number("optimise_threshold", o.optimise_threshold);
    t.number("min_dihedral_deg", o.quality.min_dihedral_deg);
    t.number("max_dihedral_deg", o.quality.max_dihedral_deg);
    t.number("min_radius_ratio", o.quality.min_radius_ratio);
  }
  {
    const fem::FibreLayoutOptions& f = spec.fibres;
    TomlTableWriter t(out, "fibres");
    t.integer("count", f.count);
    t.number("pitch_mm", f.pitch_mm);
    t.number("points_per_turn", f.points_per_turn);
    t.number("radial_inset_mm", f.radial_inset_mm);
    t.scaled("axial_stiffness_N", spec.model.fibre_axial_stiffness_uN, 1e6);
    t.boolean("tension_only", spec.model.fibres_tension_only);
  }
}

void write_ppo_table(std::ostream& out, const rl::PpoConfig& c) {
  TomlTableWriter t(out, "ppo");
  t.number("learning_rate", c.learning_rate);
  t.integer("n_steps", c.n_steps);
  t.integer("batch_size", c.batch_size);
  t.integer("n_epochs", c.n_epochs);
  t.number("gamma", c.gamma);
  t.number("gae_lambda", c.gae_lambda);
  t.number("clip_range", c.clip_range);
  t.number("ent_coef", c.ent_coef);
  if (c.ent_decay_start && c.ent_decay_end) {
    t.integer("ent_decay_start", *c.ent_decay_start);
    t.integer("ent_decay_end", *c.ent_decay_end);
  }
  if (c.lr_decay_start && c.lr_decay_end) {
    t.integer("lr_decay_start", *c.lr_decay_start);
    t.integer("lr_decay_end", *c.lr_decay_end);
    t.number("learning_rate_final", c.learning_rate_final);
  }
  t.number("vf_coef", c.vf_coef);
  t.number("max_grad_norm", c.max_grad_norm);
  if (c.target_kl) t.number("target_kl", *c.target_kl);
  t.boolean("normalize_advantage", c.normalize_advantage);
  // Only when on: the resolved config (and the checkpoint fingerprint) of a run without it is
  // what it was before the key existed, so such runs still resume.
  if (c.normalize_observations) t.boolean("normalize_observations", true);
  if (c.privileged_critic) t.boolean("privileged_critic", true);
  if (c.policy == rl::PolicyKind::Gru) {  // only when not the default, as the two keys above
    t.string("policy", name_of(rl::kPolicyKindNames, c.policy));
    t.integer("gru_hidden", c.gru_hidden);
  }
  t.integers("actor_hidden", c.actor_hidden);
  t.integers("critic_hidden", c.critic_hidden);
  t.number("log_std_init", c.log_std_init);
  if (c.log_std_min) t.number("log_std_min", *c.log_std_min);  // only when set (old fingerprints)
  t.number("adam_eps", c.adam_eps);
  t.string("matmul_precision", c.matmul_precision == rl::MatmulPrecision::BFloat16 ? "bf16" : "float32");
}

}  // namespace codesign::io
