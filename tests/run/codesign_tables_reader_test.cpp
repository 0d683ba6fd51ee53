// [task] and [codesign] tables: cross-key constraints and baseline switches.
#include <gtest/gtest.h>

#include <cmath>

#include "base/errors.hpp"
#include "core/nlopt_search.hpp"
#include "run/codesign_tables_reader.hpp"

namespace codesign::run {
namespace {

using namespace core;  // the core types these tests build

std::string error_of(const std::string& text, bool task) {
  try {
    io::TableReader r = io::TableReader::from_string(text, "run.toml");
    if (task) {
      read_task_config(r);
    } else {
      read_codesign_config(r, TaskConfig{});
    }
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ConfigReader, HoldMustDivideEpisode) {
  EXPECT_EQ(error_of("[task]\nepisode_steps = 250\naction_hold_steps = 7\n", true),
            "run.toml: task.action_hold_steps: must divide task.episode_steps (250)");
  EXPECT_EQ(error_of("[task]\nepisode_steps = 250\naction_hold_steps = 5\n", true), "");
}

TEST(ConfigReader, PhasesMustBeOrdered) {
  // T1 must come before T2: the allowed range of exploration_end ends just before T2.
  EXPECT_EQ(error_of("[codesign]\nexploration_end = 300000\nexploitation_start = 200000\n", false),
            "run.toml: codesign.exploration_end: value 300000 is out of range; allowed "
            "[0, 199999]");
}

TEST(ConfigReader, BaselineSwitch) {
  io::TableReader r = io::TableReader::from_string("[codesign]\nbaseline = \"single_design\"\n", "run.toml");
  EXPECT_EQ(read_codesign_config(r, TaskConfig{}).baseline, Baseline::SingleDesign);
  EXPECT_NE(error_of("[codesign]\nbaseline = \"random\"\n", false).find("allowed: \"none\""),
            std::string::npos);
  // The no-feedback baseline is an observation set, not a second switch.
  EXPECT_NE(error_of("[codesign]\nbaseline = \"no_feedback\"\n", false), "");
  io::TableReader t = io::TableReader::from_string("[task]\nobservation = \"no_feedback\"\n", "run.toml");
  EXPECT_EQ(read_task_config(t).observation, ObservationSet::NoFeedback);
}

// Every name of the four enum tables of [task] and [codesign] reads back as its value, the
// writer's to_string gives the name back, and a bad value's message lists every name, in the
// table's order.
TEST(ConfigReader, EnumKeysReadEveryNameOfTheirTable) {
  for (const auto& n : kObservationSetNames) {
    io::TableReader r = io::TableReader::from_string("[task]\nobservation = \"" + std::string(n.name) + "\"\n", "run.toml");
    EXPECT_EQ(read_task_config(r).observation, n.value);
    EXPECT_EQ(to_string(n.value), n.name);
  }
  for (const auto& n : kStrainOffsetNames) {
    io::TableReader r = io::TableReader::from_string("[task]\nstrain_offset = \"" + std::string(n.name) + "\"\n", "run.toml");
    EXPECT_EQ(read_task_config(r).strain_offset, n.value);
    EXPECT_EQ(to_string(n.value), n.name);
  }
  for (const auto& n : kBaselineNames) {
    io::TableReader r = io::TableReader::from_string("[codesign]\nbaseline = \"" + std::string(n.name) + "\"\n", "run.toml");
    EXPECT_EQ(read_codesign_config(r, TaskConfig{}).baseline, n.value);
    EXPECT_EQ(to_string(n.value), n.name);
  }
  for (const auto& n : kBetaScheduleNames) {
    io::TableReader r = io::TableReader::from_string("[codesign]\nbeta_schedule = \"" + std::string(n.name) + "\"\n", "run.toml");
    EXPECT_EQ(read_codesign_config(r, TaskConfig{}).distribution.beta_schedule, n.value);
    EXPECT_EQ(to_string(n.value), n.name);
  }
  EXPECT_EQ(error_of("[task]\nobservation = \"full\"\n", true),
            "run.toml: task.observation: value \"full\" is not allowed; allowed: \"paper\", \"proprioceptive\", "
            "\"no_feedback\"");
}

// [pid] method reads through the local-search table: every name, and a bad one listed against it.
TEST(ConfigReader, PidMethodReadsEveryNameOfItsTable) {
  for (const auto& n : kLocalMethodNames) {
    io::TableReader r = io::TableReader::from_string("[pid]\nmethod = \"" + std::string(n.name) + "\"\n", "run.toml");
    EXPECT_EQ(read_pid_config(r).search.method, n.value);
  }
  io::TableReader bad = io::TableReader::from_string("[pid]\nmethod = \"newton\"\n", "run.toml");
  try {
    read_pid_config(bad);
    ADD_FAILURE() << "method = newton was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "run.toml: pid.method: value \"newton\" is not allowed; allowed: \"bobyqa\", "
                                     "\"cobyla\", \"neldermead\", \"sbplx\"");
  }
}

TEST(ConfigReader, HistoryIsBoundedByTheDecisionsPerEpisode) {
  io::TableReader ok = io::TableReader::from_string("[task]\nhistory = 49\n", "run.toml");
  EXPECT_EQ(read_task_config(ok).history, 49);
  io::TableReader bad = io::TableReader::from_string("[task]\nhistory = 50\n", "run.toml");
  try {
    read_task_config(bad);
    FAIL() << "history = 50 accepted with 50 decisions per episode";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("run.toml"), std::string::npos) << m;
    EXPECT_NE(m.find("task.history"), std::string::npos) << m;
    EXPECT_NE(m.find("[0, 49]"), std::string::npos) << m;
  }
}

TEST(ConfigReader, StrainRangeMustBeOrdered) {
  EXPECT_EQ(error_of("[task]\nstrain_min = 0.1\nstrain_max = 0.05\n", true),
            "run.toml: task.strain_max: must exceed task.strain_min (0.100000)");
  EXPECT_EQ(error_of("[task]\nzeroed_strain_min = 0.001\nzeroed_strain_max = -0.001\n", true),
            "run.toml: task.zeroed_strain_max: must exceed task.zeroed_strain_min (0.001000)");
  const std::string off = error_of("[task]\nstrain_offset = \"zero\"\n", true);
  EXPECT_NE(off.find("task.strain_offset"), std::string::npos) << off;
  EXPECT_NE(off.find("inflated"), std::string::npos) << off;
}

TEST(ConfigReader, NoThetaLimitOfItsOwn) {
  // The episode ends at the scene's limit ([scene] theta_limit_deg); [task] has no second one.
  EXPECT_NE(error_of("[task]\ntheta_limit_rad = 1.0\n", true).find("task.theta_limit_rad"),
            std::string::npos);
}

TEST(ConfigReader, SingleDesignIndexRange) {
  EXPECT_EQ(error_of("[codesign]\nsingle_design_index = 110\n", false),
            "run.toml: codesign.single_design_index: value 110 is out of range; allowed [0, 109]");
}

TEST(ConfigReader, BetaScheduleAndEntropyEnd) {
  io::TableReader d = io::TableReader::from_string("", "run.toml");
  const CodesignConfig def = read_codesign_config(d, TaskConfig{});
  EXPECT_EQ(def.distribution.beta_schedule, BetaSchedule::Ramp);
  EXPECT_EQ(def.distribution.entropy_end, std::log(3.0));
  io::TableReader r = io::TableReader::from_string(
      "[codesign]\nbeta_schedule = \"entropy\"\nentropy_end = 0.25\n", "run.toml");
  const CodesignConfig c = read_codesign_config(r, TaskConfig{});
  EXPECT_EQ(c.distribution.beta_schedule, BetaSchedule::Entropy);
  EXPECT_EQ(c.distribution.entropy_end, 0.25);
  // The whole range: 0 (a point mass at T2) to ln 110 (uniform: no concentration at all).
  io::TableReader ends = io::TableReader::from_string("[codesign]\nentropy_end = 0.0\n", "run.toml");
  EXPECT_EQ(read_codesign_config(ends, TaskConfig{}).distribution.entropy_end, 0.0);
  EXPECT_EQ(error_of("[codesign]\nentropy_end = 4.7004\n", false), "");
}

TEST(ConfigReader, BadBetaScheduleAndEntropyEndNameFileKeyAndRange) {
  const std::string s = error_of("[codesign]\nbeta_schedule = \"cosine\"\n", false);
  EXPECT_EQ(s.rfind("run.toml: codesign.beta_schedule: ", 0), 0u) << s;
  EXPECT_NE(s.find("\"ramp\""), std::string::npos) << s;
  EXPECT_NE(s.find("\"entropy\""), std::string::npos) << s;
  EXPECT_EQ(error_of("[codesign]\nbeta_schedule = 1\n", false).rfind("run.toml: codesign.beta_schedule: ", 0), 0u);
  EXPECT_EQ(error_of("[codesign]\nentropy_end = 4.71\n", false),
            "run.toml: codesign.entropy_end: value 4.71 is out of range; allowed [0, 4.70048]");
  EXPECT_EQ(error_of("[codesign]\nentropy_end = -0.1\n", false),
            "run.toml: codesign.entropy_end: value -0.1 is out of range; allowed [0, 4.70048]");
  EXPECT_EQ(error_of("[codesign]\nentropy_end = nan\n", false),
            "run.toml: codesign.entropy_end: value nan is out of range; allowed [0, 4.70048]");
  const std::string t = error_of("[codesign]\nentropy_end = \"ln 3\"\n", false);
  EXPECT_EQ(t.rfind("run.toml: codesign.entropy_end: expected a number in [0, 4.70048]", 0), 0u) << t;
}

std::string pid_sweep_error(const std::string& text) {
  try {
    io::TableReader r = io::TableReader::from_string(text, "run.toml");
    read_pid_config(r);
    read_sweep_config(r, TaskConfig{});
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ConfigReader, PidAndSweepTables) {
  io::TableReader r = io::TableReader::from_string(
      "[pid]\nkp_range = [0.0, 0.3]\nmethod = \"cobyla\"\nstarts = 2\nmax_evals = 10\n"
      "[sweep]\npressures_kPa = [0.0, 20.0]\npid_strain = false\npid_estimate = false\n",
      "run.toml");
  const PidTuningConfig p = read_pid_config(r);
  EXPECT_EQ(p.box.kp[1], 0.3);
  EXPECT_EQ(p.search.method, LocalMethod::Cobyla);
  EXPECT_EQ(p.search.max_evals, 10);
  const SweepConfig s = read_sweep_config(r, TaskConfig{});
  EXPECT_EQ(s.pressures_kPa, (std::vector<double>{0.0, 20.0}));
  EXPECT_EQ(s.controllers, (std::vector<SweepController>{SweepController::FixedTheta, SweepController::PidForce}));
  EXPECT_EQ(pid_sweep_error(""), "");
}

TEST(ConfigReader, BadPidAndSweepValuesNameFileKeyAndRange) {
  EXPECT_EQ(pid_sweep_error("[pid]\nkp_range = [0.5, 0.1]\n"),
            "run.toml: pid.kp_range: lower bound 0.500000 is above upper bound 0.100000");
  EXPECT_EQ(pid_sweep_error("[pid]\nki_range = [-0.1, 0.1]\n"),
            "run.toml: pid.ki_range: element 0 = -0.1 is out of range; allowed [0, 100]");
  EXPECT_EQ(pid_sweep_error("[pid]\nstart_gains = [0.1, nan, 0.0]\n").substr(0, 24), "run.toml: pid.start_gain");
  EXPECT_EQ(pid_sweep_error("[pid]\nstarts = 5\nmax_evals = 3\n"),
            "run.toml: pid.max_evals: value 3 is out of range; allowed [5, 100000]");
  EXPECT_NE(pid_sweep_error("[pid]\nmethod = \"newton\"\n").find("pid.method"), std::string::npos);
  EXPECT_EQ(pid_sweep_error("[sweep]\npressures_kPa = [0.0, 25.0]\n"),
            "run.toml: sweep.pressures_kPa: element 1 = 25 is out of range; allowed [0, 20]");
  EXPECT_EQ(pid_sweep_error("[sweep]\nfixed_theta = false\npid_force = false\npid_strain = false\npid_estimate = false\n"),
            "run.toml: sweep.pid_estimate: fixed_theta, pid_force, pid_strain and pid_estimate are all false: nothing "
            "to sweep");
  EXPECT_NE(pid_sweep_error("[sweep]\nfirst_design = 50\nlast_design = 40\n").find("sweep.last_design"),
            std::string::npos);
}

TEST(ConfigReader, EstimatorFitEpisodesAndTheEstimateController) {
  io::TableReader r = io::TableReader::from_string("[pid]\nestimator_fit_episodes = 7\n", "run.toml");
  EXPECT_EQ(read_pid_config(r).estimator_fit_episodes, 7);
  EXPECT_EQ(PidTuningConfig{}.estimator_fit_episodes, 25);
  // The sweep's defaults list every controller, the estimate PID last.
  io::TableReader d = io::TableReader::from_string("", "run.toml");
  EXPECT_EQ(read_sweep_config(d, TaskConfig{}).controllers.back(), SweepController::PidEstimate);
  io::TableReader only = io::TableReader::from_string(
      "[sweep]\nfixed_theta = false\npid_force = false\npid_strain = false\n", "run.toml");
  EXPECT_EQ(read_sweep_config(only, TaskConfig{}).controllers, (std::vector<SweepController>{SweepController::PidEstimate}));
  EXPECT_EQ(pid_sweep_error("[pid]\nestimator_fit_episodes = 0\n"),
            "run.toml: pid.estimator_fit_episodes: value 0 is out of range; allowed [1, 1000]");
  EXPECT_EQ(pid_sweep_error("[pid]\nestimator_fit_episodes = 1001\n"),
            "run.toml: pid.estimator_fit_episodes: value 1001 is out of range; allowed [1, 1000]");
  EXPECT_NE(pid_sweep_error("[pid]\nestimator_fit_episodes = 2.5\n").find("pid.estimator_fit_episodes"),
            std::string::npos);
}

}  // namespace
}  // namespace codesign::run
