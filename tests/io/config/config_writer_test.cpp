// Config writing: write -> read back with the readers -> the same structs, field by field and
// bit for bit; writing what was read back gives the same text.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>
#include <random>
#include <sstream>
#include <string>

#include "io/config/config_writer.hpp"
#include "io/config/fem_config.hpp"
#include "io/config/gym_config.hpp"
#include "io/config/toml_reader.hpp"
#include "base/config_check.hpp"
#include "io/config/key_reference.hpp"
#include "io/config/table_keys.hpp"

using namespace codesign;

namespace {

using io::FemTables;

FemTables read_fem(const std::string& text) {
  io::TableReader root = io::TableReader::from_string(text, "resolved.toml");
  const FemTables f = io::read_fem_tables(root);
  root.finish();
  return f;
}

std::string write_fem(const FemTables& f) {
  std::ostringstream out;
  io::write_fem_tables(out, f.spec, f.scene, f.solver);
  return out.str();
}

rl::PpoConfig read_ppo(const std::string& text, const rl::PpoConfig& defaults) {
  io::TableReader root = io::TableReader::from_string(text, "resolved.toml");
  io::TableReader t = root.table("ppo");
  const rl::PpoConfig c = io::read_ppo_config(t, defaults);
  t.finish();
  root.finish();
  return c;
}

std::string write_ppo(const rl::PpoConfig& c) {
  std::ostringstream out;
  io::write_ppo_table(out, c);
  return out.str();
}

// EXPECT_EQ on doubles is ==: bit-identical for the finite, non-zero values here.
void expect_same(const FemTables& a, const FemTables& b) {
  const fem::Material &ma = a.spec.model.material, &mb = b.spec.model.material;
  EXPECT_EQ(ma.youngs_modulus_Pa, mb.youngs_modulus_Pa);
  EXPECT_EQ(ma.poisson_ratio, mb.poisson_ratio);
  EXPECT_EQ(ma.total_mass_g, mb.total_mass_g);
  EXPECT_EQ(ma.gravity_mm_s2, mb.gravity_mm_s2);
  EXPECT_EQ(ma.rayleigh_mass_per_s, mb.rayleigh_mass_per_s);
  EXPECT_EQ(ma.rayleigh_stiffness_s, mb.rayleigh_stiffness_s);
  EXPECT_EQ(a.scene.inclination_deg, b.scene.inclination_deg);
  EXPECT_EQ(a.scene.preload_mm, b.scene.preload_mm);
  EXPECT_EQ(a.scene.plate_amplitude_mm, b.scene.plate_amplitude_mm);
  EXPECT_EQ(a.scene.plate_frequency_Hz, b.scene.plate_frequency_Hz);
  EXPECT_EQ(a.scene.plate_phase_rad, b.scene.plate_phase_rad);
  EXPECT_EQ(a.scene.theta_limit_deg, b.scene.theta_limit_deg);
  EXPECT_EQ(a.scene.settle_steps, b.scene.settle_steps);
  EXPECT_EQ(a.spec.model.tip_region_mm, b.spec.model.tip_region_mm);
  EXPECT_EQ(a.solver.method, b.solver.method);
  EXPECT_EQ(a.solver.dt_s, b.solver.dt_s);
  EXPECT_EQ(a.solver.static_dt_s, b.solver.static_dt_s);
  EXPECT_EQ(a.solver.fast_tolerance, b.solver.fast_tolerance);
  EXPECT_EQ(a.solver.fast_stop, b.solver.fast_stop);
  EXPECT_EQ(a.solver.fast_max_iterations, b.solver.fast_max_iterations);
  EXPECT_EQ(a.solver.fast_refactor_iterations, b.solver.fast_refactor_iterations);
  EXPECT_EQ(a.solver.contact_tolerance_mm, b.solver.contact_tolerance_mm);
  EXPECT_EQ(a.solver.contact_margin_mm, b.solver.contact_margin_mm);
  EXPECT_EQ(a.spec.geometry.length_mm, b.spec.geometry.length_mm);
  EXPECT_EQ(a.spec.geometry.base_diameter_mm, b.spec.geometry.base_diameter_mm);
  EXPECT_EQ(a.spec.geometry.tip_diameter_mm, b.spec.geometry.tip_diameter_mm);
  EXPECT_EQ(a.spec.geometry.proximal_cap_mm, b.spec.geometry.proximal_cap_mm);
  EXPECT_EQ(a.spec.mesh.max_size_mm, b.spec.mesh.max_size_mm);
  EXPECT_EQ(a.spec.mesh.radius_factor, b.spec.mesh.radius_factor);
  EXPECT_EQ(a.spec.mesh.wall_factor, b.spec.mesh.wall_factor);
  EXPECT_EQ(a.spec.mesh.grading, b.spec.mesh.grading);
  EXPECT_EQ(a.spec.mesh.optimise_threshold, b.spec.mesh.optimise_threshold);
  EXPECT_EQ(a.spec.mesh.quality.min_dihedral_deg, b.spec.mesh.quality.min_dihedral_deg);
  EXPECT_EQ(a.spec.mesh.quality.max_dihedral_deg, b.spec.mesh.quality.max_dihedral_deg);
  EXPECT_EQ(a.spec.mesh.quality.min_radius_ratio, b.spec.mesh.quality.min_radius_ratio);
  EXPECT_EQ(a.spec.fibres.count, b.spec.fibres.count);
  EXPECT_EQ(a.spec.fibres.pitch_mm, b.spec.fibres.pitch_mm);
  EXPECT_EQ(a.spec.fibres.points_per_turn, b.spec.fibres.points_per_turn);
  EXPECT_EQ(a.spec.fibres.radial_inset_mm, b.spec.fibres.radial_inset_mm);
  EXPECT_EQ(a.spec.model.fibre_axial_stiffness_uN, b.spec.model.fibre_axial_stiffness_uN);
  EXPECT_EQ(a.spec.model.fibres_tension_only, b.spec.model.fibres_tension_only);
}

void expect_same(const rl::PpoConfig& a, const rl::PpoConfig& b) {
  EXPECT_EQ(a.learning_rate, b.learning_rate);
  EXPECT_EQ(a.n_steps, b.n_steps);
  EXPECT_EQ(a.batch_size, b.batch_size);
  EXPECT_EQ(a.n_epochs, b.n_epochs);
  EXPECT_EQ(a.gamma, b.gamma);
  EXPECT_EQ(a.gae_lambda, b.gae_lambda);
  EXPECT_EQ(a.clip_range, b.clip_range);
  EXPECT_EQ(a.ent_coef, b.ent_coef);
  EXPECT_EQ(a.ent_decay_start, b.ent_decay_start);
  EXPECT_EQ(a.ent_decay_end, b.ent_decay_end);
  EXPECT_EQ(a.vf_coef, b.vf_coef);
  EXPECT_EQ(a.max_grad_norm, b.max_grad_norm);
  EXPECT_EQ(a.target_kl, b.target_kl);
  EXPECT_EQ(a.normalize_advantage, b.normalize_advantage);
  EXPECT_EQ(a.normalize_observations, b.normalize_observations);
  EXPECT_EQ(a.privileged_critic, b.privileged_critic);
  EXPECT_EQ(a.policy, b.policy);
  EXPECT_EQ(a.gru_hidden, b.gru_hidden);
  EXPECT_EQ(a.actor_hidden, b.actor_hidden);
  EXPECT_EQ(a.critic_hidden, b.critic_hidden);
  EXPECT_EQ(a.log_std_init, b.log_std_init);
  EXPECT_EQ(a.log_std_min, b.log_std_min);
  EXPECT_EQ(a.adam_eps, b.adam_eps);
  EXPECT_EQ(a.matmul_precision, b.matmul_precision);
}

// A value in every key of every simulator table, none of them the default.
const char* const kFemNonDefault = R"(
[material]
youngs_modulus_kPa = 321.7
poisson_ratio = 0.35
total_mass_g = 17.3
gravity_mm_s2 = 9810.5
rayleigh_mass_per_s = 0.3
rayleigh_stiffness_s = 0.0071
[scene]
inclination_deg = 27.5
preload_mm = 0.7
plate_amplitude_mm = 1.9
plate_frequency_Hz = 0.65
plate_phase_deg = 37.3
theta_limit_deg = 33.0
settle_steps = 17
tip_region_mm = 7.1
[solver]
method = "exact"
dt_s = 0.005
static_dt_s = 0.7
fast_tolerance = 1e-3
fast_stop = "force"
fast_max_iterations = 40
fast_refactor_iterations = 12
contact_tolerance_mm = 3e-5
contact_margin_mm = 1.3
[geometry]
length_mm = 101.0
base_diameter_mm = 24.5
tip_diameter_mm = 4.1
proximal_cap_mm = 3.7
[mesh]
max_size_mm = 5.5
radius_factor = 0.55
wall_factor = 1.4
grading = 0.6
optimise_threshold = 0.4
min_dihedral_deg = 4.0
max_dihedral_deg = 176.0
min_radius_ratio = 0.09
[fibres]
count = 3
pitch_mm = 2.7
points_per_turn = 13.0
radial_inset_mm = 0.9
axial_stiffness_N = 43.7
tension_only = true
)";

const char* const kPpoNonDefault = R"(
[ppo]
learning_rate = 2.5e-4
n_steps = 128
batch_size = 32
n_epochs = 7
gamma = 0.97
gae_lambda = 0.9
clip_range = 0.15
ent_coef = 0.003
ent_decay_start = 1000
ent_decay_end = 9000
vf_coef = 0.7
max_grad_norm = 0.8
target_kl = 0.015
normalize_advantage = false
normalize_observations = true
privileged_critic = true
policy = "gru"
gru_hidden = 24
actor_hidden = [32, 48, 16]
critic_hidden = [96]
log_std_init = -0.5
log_std_min = -2.25
adam_eps = 1e-7
matmul_precision = "float32"
)";

}  // namespace

TEST(ConfigWriter, NumbersAreShortestFloatLiterals) {
  EXPECT_EQ(io::toml_number(0.3), "0.3");
  EXPECT_EQ(io::toml_number(500.0), "500.0");
  EXPECT_EQ(io::toml_number(-2.0), "-2.0");
  EXPECT_EQ(io::toml_number(1e-5), "1e-05");
  EXPECT_EQ(io::toml_number(std::numbers::pi / 18.0), "0.17453292519943295");
  std::ostringstream out;
  {
    io::TomlTableWriter t(out, "x");
    t.integer("big", std::int64_t{1} << 62);
    t.integers("sizes", {512, 64});
  }
  EXPECT_EQ(out.str(), "[x]\nbig = 4611686018427387904\nsizes = [512, 64]\n\n");
}

TEST(ConfigWriter, FemDefaultsRoundTrip) {
  const FemTables d = read_fem("");
  const std::string text = write_fem(d);
  const FemTables back = read_fem(text);
  expect_same(back, d);
  expect_same(back, FemTables{});  // the readers' defaults are the structs' defaults
  EXPECT_EQ(write_fem(back), text);
}

TEST(ConfigWriter, FemNonDefaultRoundTrip) {
  const FemTables a = read_fem(kFemNonDefault);
  EXPECT_EQ(a.solver.method, fem::StepMethod::Exact);
  EXPECT_NE(a.scene.plate_phase_rad, 0.0);
  const std::string text = write_fem(a);
  const FemTables back = read_fem(text);
  expect_same(back, a);
  EXPECT_EQ(write_fem(back), text);
  // Keys in their units: kPa, N and degrees as given in the file.
  EXPECT_NE(text.find("youngs_modulus_kPa = 321.7\n"), std::string::npos) << text;
  EXPECT_NE(text.find("axial_stiffness_N = 43.7\n"), std::string::npos) << text;
  EXPECT_NE(text.find("plate_phase_deg = 37.3\n"), std::string::npos) << text;
  EXPECT_NE(text.find("method = \"exact\"\n"), std::string::npos) << text;
  EXPECT_NE(text.find("fast_stop = \"force\"\n"), std::string::npos) << text;
}

// The scaled keys read back bit-identical for any value a reader produced, not only tidy ones.
TEST(ConfigWriter, ScaledKeysInvertTheReadersExactly) {
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> kpa(1.0, 1e5), newton(0.0, 1e4), deg(-360.0, 360.0);
  for (int i = 0; i < 5000; ++i) {
    std::ostringstream in;
    in.precision(17);
    in << "[material]\nyoungs_modulus_kPa = " << io::toml_number(kpa(rng)) << "\n[scene]\nplate_phase_deg = "
       << io::toml_number(deg(rng)) << "\n[fibres]\naxial_stiffness_N = " << io::toml_number(newton(rng)) << "\n";
    const FemTables a = read_fem(in.str());
    const FemTables back = read_fem(write_fem(a));
    ASSERT_EQ(back.spec.model.material.youngs_modulus_Pa, a.spec.model.material.youngs_modulus_Pa) << in.str();
    ASSERT_EQ(back.scene.plate_phase_rad, a.scene.plate_phase_rad) << in.str();
    ASSERT_EQ(back.spec.model.fibre_axial_stiffness_uN, a.spec.model.fibre_axial_stiffness_uN) << in.str();
  }
}

// A value set in code that no file value maps onto (the reader's product skips doubles: 1e3 * x
// and x * pi / 180 are not onto) is written as the nearest file value: read back within 1 ulp.
TEST(ConfigWriter, ValuesNoFileCanHoldComeBackWithinOneUlp) {
  std::mt19937_64 rng(777);
  std::uniform_real_distribution<double> pa(1e3, 1e8), rad(-6.2, 6.2), un(0.0, 1e10);
  auto within_one_ulp = [](double got, double want) {
    return got == want || got == std::nextafter(want, 1e300) || got == std::nextafter(want, -1e300);
  };
  int inexact = 0;
  for (int i = 0; i < 5000; ++i) {
    FemTables a;
    a.spec.model.material.youngs_modulus_Pa = pa(rng);
    a.scene.plate_phase_rad = rad(rng);
    a.spec.model.fibre_axial_stiffness_uN = un(rng);
    const FemTables back = read_fem(write_fem(a));
    ASSERT_TRUE(within_one_ulp(back.spec.model.material.youngs_modulus_Pa, a.spec.model.material.youngs_modulus_Pa));
    ASSERT_TRUE(within_one_ulp(back.scene.plate_phase_rad, a.scene.plate_phase_rad));
    ASSERT_TRUE(within_one_ulp(back.spec.model.fibre_axial_stiffness_uN, a.spec.model.fibre_axial_stiffness_uN));
    inexact += back.scene.plate_phase_rad != a.scene.plate_phase_rad;
  }
  EXPECT_GT(inexact, 0);  // the case exists: such values are not exact
}

TEST(ConfigWriter, PpoDefaultsRoundTrip) {
  // SB3 defaults (target_kl and the entropy decay unset: not written, read back unset).
  const rl::PpoConfig sb3 = read_ppo("", {});
  const std::string text = write_ppo(sb3);
  EXPECT_EQ(text.find("target_kl"), std::string::npos);
  EXPECT_EQ(text.find("ent_decay"), std::string::npos);
  EXPECT_EQ(text.find("log_std_min"), std::string::npos);  // unset: not written (old fingerprints)
  // The feed-forward policy is the default: its config text is what it was before ppo.policy.
  EXPECT_EQ(text.find("policy"), std::string::npos);
  EXPECT_EQ(text.find("gru_hidden"), std::string::npos);
  const rl::PpoConfig back = read_ppo(text, {});
  expect_same(back, sb3);
  EXPECT_EQ(write_ppo(back), text);
  // The paper's settings (the co-design run's defaults), read over themselves and over SB3's.
  const rl::PpoConfig paper = read_ppo("", rl::paper_ppo_config());
  const std::string paper_text = write_ppo(paper);
  expect_same(read_ppo(paper_text, rl::paper_ppo_config()), paper);
  expect_same(read_ppo(paper_text, {}), paper);
}

TEST(ConfigWriter, PpoNonDefaultRoundTrip) {
  for (const rl::PpoConfig& defaults : {rl::PpoConfig{}, rl::paper_ppo_config()}) {
    const rl::PpoConfig a = read_ppo(kPpoNonDefault, defaults);
    EXPECT_EQ(a.actor_hidden, (std::vector<int>{32, 48, 16}));
    EXPECT_EQ(a.policy, rl::PolicyKind::Gru);
    EXPECT_EQ(a.gru_hidden, 24);
    const std::string text = write_ppo(a);
    const rl::PpoConfig back = read_ppo(text, defaults);
    expect_same(back, a);
    EXPECT_EQ(write_ppo(back), text);
  }
}

TEST(ConfigWriter, PpoPrecisionIsTheResolvedOne) {
  const rl::PpoConfig a = read_ppo("[ppo]\nmatmul_precision = \"auto\"\n", {});
  const std::string text = write_ppo(a);
  EXPECT_EQ(text.find("\"auto\""), std::string::npos);
  const std::string expected = rl::resolve(rl::MatmulChoice::Auto) == rl::MatmulPrecision::BFloat16 ? "bf16" : "float32";
  EXPECT_NE(text.find("matmul_precision = \"" + expected + "\"\n"), std::string::npos) << text;
  EXPECT_EQ(read_ppo(text, {}).matmul_precision, a.matmul_precision);
}

namespace codesign {
namespace {

// A table with one grid key, through every visitor of the key descriptions: the reader expands a
// {from, to, step}, the writer states the array it gave, which reads back the same; the check and
// the reference page see the key.
struct GridHolder {
  std::vector<double> walls{2.0, 2.5};
};
template <class V>
void describe_grid_holder(V& v, GridHolder& h) {
  v.grid({"wall_mm", "mm", "wall thicknesses"}, h.walls, {0.5, 10.0}, {1, 50});
}

TEST(GridKey, ReadsARangeWritesItsArrayAndReadsThatBack) {
  GridHolder h;
  io::TableReader root = io::TableReader::from_string("[space]\nwall_mm = {from = 1.5, to = 3.0, step = 0.5}\n", "s.toml");
  io::read_keys(root, "space", [&](auto& v) { describe_grid_holder(v, h); });
  EXPECT_EQ(h.walls, (std::vector<double>{1.5, 2.0, 2.5, 3.0}));
  std::ostringstream out;
  io::write_keys(out, "space", [&](auto& v) { describe_grid_holder(v, h); });
  EXPECT_NE(out.str().find("wall_mm = [1.5, 2.0, 2.5, 3.0]"), std::string::npos) << out.str();
  GridHolder back;
  io::TableReader again = io::TableReader::from_string(out.str(), "written.toml");
  io::read_keys(again, "space", [&](auto& v) { describe_grid_holder(v, back); });
  EXPECT_EQ(back.walls, h.walls);

  h.walls.push_back(20.0);
  const std::optional<std::string> p = config::first_problem([&](auto& v) { describe_grid_holder(v, h); });
  ASSERT_TRUE(p.has_value());
  EXPECT_NE(p->find("wall_mm"), std::string::npos) << *p;
  const std::vector<io::KeyRow> rows = io::key_rows([&](auto& v) { describe_grid_holder(v, h); });
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].type, "array of floats or {from, to, step}");
}

}  // namespace
}  // namespace codesign
