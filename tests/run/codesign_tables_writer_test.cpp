// The resolved config of a run: every table the run reads, read back with the readers the run
// uses, gives the same values; resolving what was read back gives the same text.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "run/codesign_tables_reader.hpp"
#include "run/codesign_tables_writer.hpp"
#include "core/outer_loop.hpp"
#include "test_files.hpp"
#include "io/config/config_writer.hpp"
#include "io/config/fem_config.hpp"
#include "io/config/render_config.hpp"
#include "io/config/toml_reader.hpp"
#include "io/config/gym_config.hpp"

namespace codesign::run {
namespace {

using namespace core;  // the core types these tests build

using codesign::test_files::slurp;

struct RunTables {
  io::FemTables fem;
  LoopConfig loop;
};

// A run config read as `codesign run` reads it (run/run_config.cpp; [sim] and [render] read and
// dropped: they are not part of the resolved config).
RunTables read_run(const std::string& text) {
  io::TableReader root = io::TableReader::from_string(text, "run.toml");
  RunTables r;
  r.fem = io::read_fem_tables(root);
  io::read_sim_scenario(root);
  io::read_render_config(root);
  r.loop.task = read_task_config(root);
  r.loop.codesign = read_codesign_config(root, r.loop.task);
  io::TableReader ppo = root.table("ppo");
  r.loop.ppo = io::read_ppo_config(ppo, rl::paper_ppo_config());
  ppo.finish();
  root.finish();
  return r;
}

std::string resolved(const RunTables& r) { return resolved_run_config(r.fem.spec, r.fem.scene, r.fem.solver, r.loop); }

void expect_same(const TaskConfig& a, const TaskConfig& b) {
  EXPECT_EQ(a.episode_steps, b.episode_steps);
  EXPECT_EQ(a.action_hold_steps, b.action_hold_steps);
  EXPECT_EQ(a.theta_max_rad, b.theta_max_rad);
  EXPECT_EQ(a.target_force_mN, b.target_force_mN);
  EXPECT_EQ(a.tolerance_fraction, b.tolerance_fraction);
  EXPECT_EQ(a.kappa, b.kappa);
  EXPECT_EQ(a.smooth_penalty, b.smooth_penalty);
  EXPECT_EQ(a.flip_penalty, b.flip_penalty);
  EXPECT_EQ(a.observation, b.observation);
  EXPECT_EQ(a.strain_min, b.strain_min);
  EXPECT_EQ(a.strain_max, b.strain_max);
  EXPECT_EQ(a.strain_offset, b.strain_offset);
  EXPECT_EQ(a.zeroed_strain_min, b.zeroed_strain_min);
  EXPECT_EQ(a.zeroed_strain_max, b.zeroed_strain_max);
  EXPECT_EQ(a.pressure_max_kPa, b.pressure_max_kPa);
}

void expect_same(const CodesignConfig& a, const CodesignConfig& b) {
  EXPECT_EQ(a.total_timesteps, b.total_timesteps);
  EXPECT_EQ(a.designs_per_update, b.designs_per_update);
  EXPECT_EQ(a.distribution.exploration_end, b.distribution.exploration_end);
  EXPECT_EQ(a.distribution.exploitation_start, b.distribution.exploitation_start);
  EXPECT_EQ(a.distribution.alpha, b.distribution.alpha);
  EXPECT_EQ(a.distribution.phi, b.distribution.phi);
  EXPECT_EQ(a.distribution.beta_start, b.distribution.beta_start);
  EXPECT_EQ(a.distribution.beta_end, b.distribution.beta_end);
  EXPECT_EQ(a.distribution.beta_schedule, b.distribution.beta_schedule);
  EXPECT_EQ(a.distribution.entropy_end, b.distribution.entropy_end);
  EXPECT_EQ(a.distribution.reward_buffer, b.distribution.reward_buffer);
  EXPECT_EQ(a.distribution.latent_mu0, b.distribution.latent_mu0);
  EXPECT_EQ(a.distribution.latent_sigma0, b.distribution.latent_sigma0);
  EXPECT_EQ(a.distribution.latent_sigma_min, b.distribution.latent_sigma_min);
  EXPECT_EQ(a.baseline, b.baseline);
  EXPECT_EQ(a.single_design_index, b.single_design_index);
  EXPECT_EQ(a.single_design_p1_kPa, b.single_design_p1_kPa);
  EXPECT_EQ(a.single_design_p2_kPa, b.single_design_p2_kPa);
  EXPECT_EQ(a.random_plate_phase, b.random_plate_phase);
  EXPECT_EQ(a.plate_phase_rad, b.plate_phase_rad);
  EXPECT_EQ(a.eval_episodes, b.eval_episodes);
  EXPECT_EQ(a.fixed_theta_phases, b.fixed_theta_phases);
  EXPECT_EQ(a.checkpoint_every, b.checkpoint_every);
  EXPECT_EQ(a.seed, b.seed);
}

// Field by field for [task] and [codesign]; the simulator and [ppo] tables are compared field
// by field in tests/io/config/config_writer_test.cpp, here through their text (one text per value:
// every field is written in a form that reads back onto it exactly).
void expect_same(const RunTables& a, const RunTables& b) {
  expect_same(a.loop.task, b.loop.task);
  expect_same(a.loop.codesign, b.loop.codesign);
  std::ostringstream fa, fb;
  io::write_fem_tables(fa, a.fem.spec, a.fem.scene, a.fem.solver);
  io::write_fem_tables(fb, b.fem.spec, b.fem.scene, b.fem.solver);
  EXPECT_EQ(fa.str(), fb.str());
  std::ostringstream pa, pb;
  io::write_ppo_table(pa, a.loop.ppo);
  io::write_ppo_table(pb, b.loop.ppo);
  EXPECT_EQ(pa.str(), pb.str());
}

// Read `text`, resolve, read that back: the same values; resolving again: the same text.
std::string check_round_trip(const std::string& text) {
  const RunTables a = read_run(text);
  const std::string r = resolved(a);
  const RunTables back = read_run(r);
  expect_same(back, a);
  EXPECT_EQ(resolved(back), r);
  return r;
}

// A value in every key of [task] and [codesign], none of them the default, and one changed
// key in each simulator table and [ppo] (tests/io covers every key of those).
const char* const kNonDefault = R"(
[material]
youngs_modulus_kPa = 450.5
[scene]
plate_phase_deg = -12.5
tip_region_mm = 5.5
[solver]
method = "exact"
[geometry]
proximal_cap_mm = 3.5
[mesh]
grading = 0.45
[fibres]
count = 1
axial_stiffness_N = 12.5
[task]
episode_steps = 200
action_hold_steps = 4
theta_max_rad = 0.15
target_force_mN = 18.5
tolerance_fraction = 0.25
kappa = 1.7
smooth_penalty = 0.07
flip_penalty = 0.12
observation = "proprioceptive"
strain_min = -0.01
strain_max = 0.05
strain_offset = "inflated"
zeroed_strain_min = -0.0011
zeroed_strain_max = 0.0002
pressure_max_kPa = 15.0
[codesign]
total_timesteps = 500000
designs_per_update = 20
exploitation_start = 400000
exploration_end = 100000
alpha = 0.2
phi = 0.07
beta_start = 0.1
beta_end = 0.9
beta_schedule = "entropy"
entropy_end = 0.75
reward_buffer = 50
latent_mu0 = 0.3
latent_sigma0 = 0.8
latent_sigma_min = 0.002
baseline = "single_design"
single_design_index = 7
single_design_p1_kPa = 3.5
single_design_p2_kPa = 1.25
random_plate_phase = false
plate_phase_deg = 45.0
eval_episodes = 20
fixed_theta_phases = 0
checkpoint_every = 10000
seed = 4611686018427387904
[ppo]
target_kl = 0.03
ent_decay_start = 1000
ent_decay_end = 2000
lr_decay_start = 1500
lr_decay_end = 2500
learning_rate_final = 0.00003
matmul_precision = "float32"
)";

}  // namespace

TEST(ResolvedConfig, DefaultsRoundTrip) {
  const std::string r = check_round_trip("");
  EXPECT_EQ(r.rfind("# resolved by codesign: every key the run reads, with the value used\n", 0), 0u) << r;
  for (const char* table : {"[material]", "[scene]", "[solver]", "[geometry]", "[mesh]", "[fibres]", "[task]",
                            "[codesign]", "[ppo]"})
    EXPECT_NE(r.find(std::string("\n") + table + "\n"), std::string::npos) << table;
  EXPECT_EQ(r.find("[sim]"), std::string::npos);
  // Defaults are filled in, e.g. the paper's PPO settings and the value types' defaults.
  EXPECT_NE(r.find("\ntarget_kl = 0.02\n"), std::string::npos) << r;
  EXPECT_NE(r.find("\nobservation = \"paper\"\n"), std::string::npos) << r;
  EXPECT_NE(r.find("\nbaseline = \"none\"\n"), std::string::npos) << r;
  EXPECT_EQ(r.find("\"auto\""), std::string::npos) << r;
  // Keys written only when not their default (so that older runs' config.toml stays as it was).
  EXPECT_EQ(r.find("beta_schedule"), std::string::npos) << r;
  EXPECT_EQ(r.find("entropy_end"), std::string::npos) << r;
  // The value types' defaults.
  const RunTables d = read_run("");
  expect_same(d.loop.task, TaskConfig{});
  expect_same(d.loop.codesign, CodesignConfig{});
}

TEST(ResolvedConfig, NonDefaultRoundTrip) {
  const RunTables a = read_run(kNonDefault);
  EXPECT_EQ(a.loop.task.observation, ObservationSet::Proprioceptive);
  EXPECT_EQ(a.loop.codesign.baseline, Baseline::SingleDesign);
  EXPECT_EQ(a.loop.codesign.seed, std::uint64_t{1} << 62);
  EXPECT_EQ(a.loop.codesign.distribution.beta_schedule, BetaSchedule::Entropy);
  EXPECT_EQ(a.loop.codesign.distribution.entropy_end, 0.75);
  const std::string r = check_round_trip(kNonDefault);
  EXPECT_NE(r.find("\nplate_phase_deg = -12.5\n"), std::string::npos) << r;  // [scene]
  EXPECT_NE(r.find("\nplate_phase_deg = 45.0\n"), std::string::npos) << r;   // [codesign]
  EXPECT_NE(r.find("\nseed = 4611686018427387904\n"), std::string::npos) << r;
  EXPECT_NE(r.find("\nbeta_end = 0.9\nbeta_schedule = \"entropy\"\nentropy_end = 0.75\n"), std::string::npos) << r;
  EXPECT_NE(r.find("\nlr_decay_start = 1500\nlr_decay_end = 2500\nlearning_rate_final = 3e-05\n"), std::string::npos) << r;
}

TEST(ResolvedConfig, NoFeedbackObservation) {
  check_round_trip("[task]\nobservation = \"no_feedback\"\n");
}

TEST(ResolvedConfig, ShippedConfigsRoundTrip) {
  for (const char* name : {"configs/paper.toml", "configs/quick.toml"}) {
    SCOPED_TRACE(name);
    const std::string text = slurp(std::string(CODESIGN_SOURCE_DIR) + "/" + name);
    ASSERT_FALSE(text.empty());
    check_round_trip(text);
  }
}

// The paper's variants extend paper.toml and differ from it in exactly the keys they state; their
// merged text (what config.input.toml records) reads back to the same run.
TEST(ResolvedConfig, PaperVariantsDifferOnlyWhereTheySay) {
  const std::string dir = std::string(CODESIGN_SOURCE_DIR) + "/configs/";
  const RunTables paper = read_run(slurp(dir + "paper.toml"));
  const auto variant = [&](const char* name) {
    SCOPED_TRACE(name);
    const std::string merged = io::TableReader::input_text(dir + name);
    EXPECT_EQ(merged.rfind("# " + dir + name + " extends ", 0), 0u) << merged;
    check_round_trip(merged);
    return read_run(merged);
  };
  RunTables nf = variant("paper_no_feedback.toml");
  EXPECT_EQ(nf.loop.task.observation, ObservationSet::NoFeedback);
  nf.loop.task.observation = paper.loop.task.observation;
  EXPECT_EQ(resolved(nf), resolved(paper));

  RunTables pr = variant("paper_proprioceptive.toml");
  EXPECT_EQ(pr.loop.task.observation, ObservationSet::Proprioceptive);
  pr.loop.task.observation = paper.loop.task.observation;
  EXPECT_EQ(resolved(pr), resolved(paper));

  RunTables sd = variant("paper_single_design.toml");
  EXPECT_EQ(sd.loop.codesign.baseline, Baseline::SingleDesign);
  EXPECT_EQ(sd.loop.codesign.single_design_index, 47);  // d* of our paper run (docs/journal/results.md)
  sd.loop.codesign.baseline = paper.loop.codesign.baseline;
  sd.loop.codesign.single_design_index = paper.loop.codesign.single_design_index;
  sd.loop.codesign.single_design_p1_kPa = paper.loop.codesign.single_design_p1_kPa;
  sd.loop.codesign.single_design_p2_kPa = paper.loop.codesign.single_design_p2_kPa;
  EXPECT_EQ(resolved(sd), resolved(paper));
}

// configs/quick_entropy.toml is quick.toml with the entropy schedule and nothing else.
TEST(ResolvedConfig, QuickEntropyDiffersFromQuickOnlyInTheSchedule) {
  const std::string dir = std::string(CODESIGN_SOURCE_DIR) + "/configs/";
  const RunTables quick = read_run(slurp(dir + "quick.toml"));
  const std::string merged = io::TableReader::input_text(dir + "quick_entropy.toml");
  check_round_trip(merged);
  RunTables e = read_run(merged);
  EXPECT_EQ(e.loop.codesign.distribution.beta_schedule, BetaSchedule::Entropy);
  EXPECT_EQ(e.loop.codesign.distribution.entropy_end, std::log(3.0));
  EXPECT_EQ(resolved(e).find("entropy_end"), std::string::npos);  // the default: not written
  e.loop.codesign.distribution.beta_schedule = quick.loop.codesign.distribution.beta_schedule;
  EXPECT_EQ(resolved(e), resolved(quick));
}

}  // namespace codesign::run
