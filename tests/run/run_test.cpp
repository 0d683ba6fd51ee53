// A whole run: its folder, resuming from a checkpoint with the same final result, and bad
// checkpoints or folders that stop with a clear error and lose nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <algorithm>
#include <map>
#include <memory>
#include <numbers>
#include <sstream>
#include <string>


#include "base/errors.hpp"
#include "run/checkpoint.hpp"
#include "core/design_sweep.hpp"
#include "core/policy_controller.hpp"
#include "run/run.hpp"
#include "test_files.hpp"
#include "io/formats/csv_table.hpp"
#include "io/telemetry/telemetry.hpp"
#include "rl/policy_file.hpp"
#include "lcm/eventlog.h"
#include "test_setup.hpp"

namespace {

namespace fs = std::filesystem;
using namespace codesign;
using namespace codesign::core;
using namespace codesign::run;
using codesign::test_files::slurp;

// result.toml without its wall-clock line.
std::string result_without_wall(const fs::path& dir) {
  std::istringstream in(slurp(dir / "result.toml"));
  std::string line, out;
  while (std::getline(in, line))
    if (line.rfind("wall_s", 0) != 0) out += line + "\n";
  return out;
}

RunOptions opts(const fs::path& dir) {
  RunOptions o;
  o.dir = dir.string();
  o.threads = 2;
  o.progress = false;
  return o;
}

TEST(Run, WritesTheRunFolder) {
  const fs::path d = test_files::fresh_dir("run_folder");
  const RunResult r = run_codesign(test::tiny_run(), opts(d));
  EXPECT_TRUE(r.completed);
  for (const char* f : {"config.toml", "config.input.toml", "episodes.csv", "ppo.csv", "distribution.csv", "q_disc.csv", "sampled.csv",
                        "checkpoint.bin", "policy.bin", "result.toml", "eval/best.csv", "eval/best_trace.csv",
                        "eval/runner_up.csv", "eval/runner_up_trace.csv"})
    EXPECT_TRUE(fs::exists(d / f)) << f;
  const std::string res = slurp(d / "result.toml");
  for (const char* key : {"[best]", "[runner_up]", "[run]", "test_return", "band_fraction", "pressures_kPa", "wall_s"})
    EXPECT_NE(res.find(key), std::string::npos) << key;
  // The fixed-angle reference on d*: the same numbers as tune_fixed_theta on d* at p* with the
  // run's phases, tested on the run's test episodes.
  const RunSettings s = test::tiny_run();
  auto sims = std::make_shared<SimulatorPool>(s.spec, s.scene, s.solver);
  const auto table = [&](const std::string& section, const std::string& key) {
    const auto at = res.find("[" + section + "]");
    EXPECT_NE(at, std::string::npos) << section;
    const auto k = res.find("\n" + key + " = ", at);
    return k == std::string::npos ? std::string() : res.substr(k + key.size() + 4, res.find_first_of(" \n", k + key.size() + 4) - (k + key.size() + 4));
  };
  const int design = std::stoi(table("best", "design"));
  const double p1 = std::stod(res.substr(res.find("pressures_kPa = [", res.find("[best]")) + 17));
  const double p2 = std::stod(res.substr(res.find(", ", res.find("pressures_kPa = [", res.find("[best]"))) + 2));
  const FixedThetaTuning ft = tune_fixed_theta(sims, s.loop.task, {design, p1, p2, 0.0, 0.0}, FixedThetaConfig{}, 2,
                                               s.loop.codesign.eval_episodes, 1);
  EXPECT_DOUBLE_EQ(std::stod(table("best_fixed_theta", "test_return")), ft.test.mean_return);
  // (degrees in the file: the conversion back may differ in the last bits)
  EXPECT_NEAR(std::stod(table("best_fixed_theta", "theta0_deg")) * std::numbers::pi / 180.0, ft.theta0_rad, 1e-12);
  // The ramp's distribution.csv has the columns it had before the entropy schedule existed.
  EXPECT_EQ(slurp(d / "distribution.csv").substr(0, slurp(d / "distribution.csv").find('\n')),
            "k,t,phase,beta,entropy,top1_j,top1_q,top2_j,top2_q,top3_j,top3_q,best_j,best_score,best_mu1_kPa,"
            "best_mu2_kPa,best_sigma1_kPa,best_sigma2_kPa");
  // ppo.csv: header + 6 updates.
  std::istringstream ppo(slurp(d / "ppo.csv"));
  int lines = 0;
  for (std::string l; std::getline(ppo, l);) ++lines;
  EXPECT_EQ(lines, 7);
}

TEST(Run, ResumedRunEndsIdentically) {
  const fs::path a = test_files::fresh_dir("run_whole"), b = test_files::fresh_dir("run_resumed");
  ASSERT_TRUE(run_codesign(test::tiny_run(), opts(a)).completed);
  RunOptions o = opts(b);
  o.stop_after = 60;  // between checkpoints (every 20): the logs hold rows past the checkpoint
  ASSERT_FALSE(run_codesign(test::tiny_run(), o).completed);
  o.stop_after = -1;
  o.resume = true;
  ASSERT_TRUE(run_codesign(test::tiny_run(), o).completed);
  EXPECT_EQ(slurp(a / "policy.bin"), slurp(b / "policy.bin"));
  EXPECT_EQ(result_without_wall(a), result_without_wall(b));
  EXPECT_EQ(slurp(a / "episodes.csv"), slurp(b / "episodes.csv"));
  EXPECT_EQ(slurp(a / "q_disc.csv"), slurp(b / "q_disc.csv"));
}

// The states after the iterations that reach T1 and T2 are kept beside checkpoint.bin, each the
// same state as the checkpoint of a run stopped there; a fresh run removes an earlier run's.
TEST(Run, KeepsTheCheckpointsAtT1AndT2) {
  const fs::path a = test_files::fresh_dir("run_kept");
  ASSERT_TRUE(run_codesign(test::tiny_run(), opts(a)).completed);
  const std::uint64_t fp = fingerprint(slurp(a / "config.toml"));
  const std::vector<KeptCheckpoint> kept = kept_checkpoints(test::tiny_run().loop.codesign);
  ASSERT_EQ(kept.size(), 2u);
  for (const KeptCheckpoint& kc : kept) {
    SCOPED_TRACE(kc.file);
    const fs::path b = test_files::fresh_dir("run_kept_stop_" + kc.name);
    RunOptions o = opts(b);
    o.stop_after = kc.t;
    ASSERT_FALSE(run_codesign(test::tiny_run(), o).completed);
    const Checkpoint k = load_checkpoint((a / kc.file).string(), fp);
    const Checkpoint s = load_checkpoint((b / "checkpoint.bin").string(), fp);
    EXPECT_EQ(k.loop.t, kc.t);  // tiny_run's T1 = 40 and T2 = 80 end an iteration of 20
    EXPECT_EQ(k.loop.t, s.loop.t);
    EXPECT_EQ(k.loop.k, s.loop.k);
    EXPECT_TRUE(k.loop.actor == s.loop.actor);
    EXPECT_TRUE(k.loop.critic == s.loop.critic);
    EXPECT_EQ(k.loop.rng_design, s.loop.rng_design);
    EXPECT_TRUE(k.loop.distribution.score == s.loop.distribution.score);
    // (the logs' byte lengths may differ: ppo.csv holds wall times)
    EXPECT_EQ(k.logs.size(), s.logs.size());
  }
  // --force starts afresh: a run stopped before T1 leaves no kept file of the earlier run.
  RunOptions o = opts(a);
  o.force = true;
  o.stop_after = 20;
  ASSERT_FALSE(run_codesign(test::tiny_run(), o).completed);
  for (const KeptCheckpoint& kc : kept) EXPECT_FALSE(fs::exists(a / kc.file)) << kc.file;
}

// Memory and observation normalisation carry through checkpoint (version 2), resume, policy
// file and evaluation: the resumed run ends with the same files.
TEST(Run, ResumedRunWithHistoryAndObservationNormalisationEndsIdentically) {
  RunSettings s = test::tiny_run();
  s.loop.task.history = 4;
  s.loop.ppo.normalize_observations = true;
  s.config_text += "# history 4, normalised observations\n";
  const fs::path a = test_files::fresh_dir("run_norm_whole"), b = test_files::fresh_dir("run_norm_resumed");
  ASSERT_TRUE(run_codesign(s, opts(a)).completed);
  RunOptions o = opts(b);
  o.stop_after = 60;
  ASSERT_FALSE(run_codesign(s, o).completed);
  o.stop_after = -1;
  o.resume = true;
  ASSERT_TRUE(run_codesign(s, o).completed);
  EXPECT_EQ(slurp(a / "policy.bin"), slurp(b / "policy.bin"));
  EXPECT_EQ(result_without_wall(a), result_without_wall(b));
  EXPECT_EQ(slurp(a / "episodes.csv"), slurp(b / "episodes.csv"));
  const rl::Policy policy = rl::Policy::load(a / "policy.bin");
  ASSERT_TRUE(policy.obs_norm().has_value());
  EXPECT_EQ(policy.obs_dim(), 7 + 4 * 3);  // proprioceptive + 4 decisions of ε, θ and action
  // The statistics saw real observations: the design components vary across designs.
  EXPECT_GT(policy.obs_norm()->var[0], 0.0);
  EXPECT_LT(policy.obs_norm()->var[0], 1.0);
}

// The entropy schedule: distribution.csv gains a target_entropy column, which follows the line
// from ln 110 at T1 = 40 to entropy_end at T2 = 80; the entropy meets it from below, or stays at
// the floor ln(number of designs tied at the top); a resumed run writes the same file.
TEST(Run, EntropyScheduleLogsItsTargetAndResumesIdentically) {
  RunSettings s = test::tiny_run();
  s.loop.codesign.distribution.beta_schedule = BetaSchedule::Entropy;
  s.loop.codesign.distribution.entropy_end = 2.0;
  s.config_text += "# entropy schedule\n";
  const fs::path a = test_files::fresh_dir("run_entropy_whole"), b = test_files::fresh_dir("run_entropy_resumed");
  ASSERT_TRUE(run_codesign(s, opts(a)).completed);
  RunOptions o = opts(b);
  o.stop_after = 60;
  ASSERT_FALSE(run_codesign(s, o).completed);
  o.stop_after = -1;
  o.resume = true;
  ASSERT_TRUE(run_codesign(s, o).completed);
  EXPECT_EQ(slurp(a / "distribution.csv"), slurp(b / "distribution.csv"));
  EXPECT_EQ(slurp(a / "policy.bin"), slurp(b / "policy.bin"));
  EXPECT_NE(slurp(a / "config.toml").find("\nbeta_schedule = \"entropy\"\nentropy_end = 2.0\n"), std::string::npos);

  const io::CsvTable d = io::read_csv((a / "distribution.csv").string());
  ASSERT_EQ(d.rows(), 6u);
  EXPECT_EQ(d.column("target_entropy"), d.column("entropy") + 1);
  const double ln110 = std::log(110.0);
  const std::map<std::int64_t, double> target{{20, ln110}, {40, ln110}, {60, ln110 + 0.5 * (2.0 - ln110)},
                                              {80, 2.0}, {100, 2.0}, {120, 2.0}};
  for (std::size_t r = 0; r < d.rows(); ++r) {
    const std::int64_t t = d.integer(r, d.column("t"));
    SCOPED_TRACE(t);
    const double h = d.number(r, d.column("entropy")), beta = d.number(r, d.column("beta"));
    EXPECT_EQ(d.number(r, d.column("target_entropy")), target.at(t));
    if (t < 60) {
      EXPECT_EQ(beta, 0.0);  // exploration, and T1 itself (target ln 110)
    } else if (h <= target.at(t)) {
      EXPECT_GE(h, target.at(t) - 1e-9);
    } else {
      // Above the target only at the floor: q uniform over m designs tied at the top, H = ln m.
      // (Here the returns are negative: the designs never sampled keep R̂ = 0 and tie at the top.)
      EXPECT_GT(beta, 0.0);
      EXPECT_NEAR(h, std::log(std::round(std::exp(h))), 1e-12);
      EXPECT_NEAR(d.number(r, d.column("top1_q")), 1.0 / std::round(std::exp(h)), 1e-15);
    }
  }
}

// A recurrent policy (ppo.policy = "gru") carries through checkpoint (version 3), resume, policy
// file (version 3) and evaluation: the resumed run ends with the same files, and the test return
// in result.toml is what the policy file gives with one fresh hidden state per episode.
TEST(Run, ResumedRecurrentRunEndsIdenticallyAndItsPolicyFileReproducesTheEvaluation) {
  RunSettings s = test::tiny_run();
  s.loop.ppo.policy = rl::PolicyKind::Gru;
  s.loop.ppo.gru_hidden = 8;
  s.loop.ppo.normalize_observations = true;
  s.config_text += "# recurrent policy\n";
  const fs::path a = test_files::fresh_dir("run_gru_whole"), b = test_files::fresh_dir("run_gru_resumed");
  ASSERT_TRUE(run_codesign(s, opts(a)).completed);
  EXPECT_EQ(slurp(a / "checkpoint.bin")[8], 3);
  EXPECT_EQ(slurp(a / "policy.bin")[8], 3);
  RunOptions o = opts(b);
  o.stop_after = 60;
  ASSERT_FALSE(run_codesign(s, o).completed);
  o.stop_after = -1;
  o.resume = true;
  ASSERT_TRUE(run_codesign(s, o).completed);
  EXPECT_EQ(slurp(a / "policy.bin"), slurp(b / "policy.bin"));
  EXPECT_EQ(result_without_wall(a), result_without_wall(b));
  EXPECT_EQ(slurp(a / "episodes.csv"), slurp(b / "episodes.csv"));

  const auto policy = std::make_shared<const rl::Policy>(rl::Policy::load(a / "policy.bin"));
  ASSERT_TRUE(policy->recurrent());
  ASSERT_TRUE(policy->obs_norm().has_value());
  const std::string res = slurp(a / "result.toml");
  const auto best = res.find("[best]");
  const int design = std::stoi(res.substr(res.find("design = ", best) + 9));
  const double p1 = std::stod(res.substr(res.find("pressures_kPa = [", best) + 17));
  const double p2 = std::stod(res.substr(res.find(", ", res.find("pressures_kPa = [", best)) + 2));
  const double test_return = std::stod(res.substr(res.find("test_return = ", best) + 14));
  auto sims = std::make_shared<SimulatorPool>(s.spec, s.scene, s.solver);
  EvaluationOptions eo;
  eo.episodes = s.loop.codesign.eval_episodes;
  eo.threads = 2;
  const DesignEvaluation e = evaluate_feedback(policy_factory(policy), sims, s.loop.task, {design, p1, p2, 0.0, 0.0}, eo);
  EXPECT_NEAR(e.mean_return, test_return, 1e-9 * (1 + std::abs(test_return)));  // result.toml prints 17 digits
}

TEST(Run, RefusesToOverwriteAnEarlierRun) {
  const fs::path d = test_files::fresh_dir("run_refuse");
  RunOptions o = opts(d);
  o.stop_after = 20;
  run_codesign(test::tiny_run(), o);
  const std::string before = slurp(d / "episodes.csv");
  o.stop_after = -1;
  EXPECT_THROW(run_codesign(test::tiny_run(), o), InputError);
  EXPECT_EQ(slurp(d / "episodes.csv"), before);
}

TEST(Run, MismatchedOrDamagedCheckpointIsAClearErrorAndChangesNothing) {
  const fs::path d = test_files::fresh_dir("run_damaged");
  RunOptions o = opts(d);
  o.stop_after = 40;
  run_codesign(test::tiny_run(), o);
  const std::string episodes = slurp(d / "episodes.csv"), ckpt = slurp(d / "checkpoint.bin");
  o.stop_after = -1;
  o.resume = true;
  // Another config.
  try {
    run_codesign(test::tiny_run(8), o);
    ADD_FAILURE() << "resumed with another config";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("another config"), std::string::npos) << e.what();
  }
  // One flipped byte.
  std::string bad = ckpt;
  bad[bad.size() / 2] ^= 0x20;
  std::ofstream(d / "checkpoint.bin", std::ios::binary) << bad;
  try {
    run_codesign(test::tiny_run(), o);
    ADD_FAILURE() << "resumed from a damaged checkpoint";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("checksum"), std::string::npos) << e.what();
  }
  // Truncated.
  std::ofstream(d / "checkpoint.bin", std::ios::binary | std::ios::trunc) << ckpt.substr(0, ckpt.size() / 3);
  EXPECT_THROW(run_codesign(test::tiny_run(), o), InputError);
  EXPECT_EQ(slurp(d / "episodes.csv"), episodes);
}

}  // namespace

namespace {

TEST(Run, TelemetryLogHoldsEveryChannelAndChangesNothing) {
  const fs::path plain = test_files::fresh_dir("run_tel_off"), logged = test_files::fresh_dir("run_tel_on");
  ASSERT_TRUE(run_codesign(test::tiny_run(), opts(plain)).completed);
  RunOptions o = opts(logged);
  fs::create_directories(logged);
  const fs::path log = logged / "telemetry.lcm";
  o.telemetry_url = "file://" + log.string() + "?mode=w";
  const RunResult on = run_codesign(test::tiny_run(), o);
  ASSERT_TRUE(on.completed);
  EXPECT_EQ(slurp(plain / "policy.bin"), slurp(logged / "policy.bin"));

  std::map<std::string, int> count;
  std::vector<codesign_lcm::sim_step_t> training;
  lcm_eventlog_t* in = lcm_eventlog_create(log.c_str(), "r");
  ASSERT_NE(in, nullptr);
  while (lcm_eventlog_event_t* e = lcm_eventlog_read_next_event(in)) {
    const std::string channel(e->channel, e->channellen);
    ++count[channel];
    if (channel == "CODESIGN_TRAIN_STEP") {
      codesign_lcm::sim_step_t m;
      EXPECT_EQ(m.decode(e->data, 0, e->datalen), e->datalen);
      training.push_back(m);
    }
    lcm_eventlog_free_event(e);
  }
  lcm_eventlog_destroy(in);
  // 6 iterations; one message per row of episodes.csv; the steps of the first evaluation
  // episode of d* and of the runner-up, as in their trace files.
  auto rows = [&](const fs::path& f) {
    const std::string text = slurp(f);
    return static_cast<int>(std::count(text.begin(), text.end(), '\n')) - 1;  // minus the header
  };
  EXPECT_EQ(count["CODESIGN_PPO"], 6);
  EXPECT_EQ(count["CODESIGN_DISTRIBUTION"], 6);
  EXPECT_EQ(count["CODESIGN_POLICY_MEMORY"], 0);  // a feed-forward policy has no memory
  EXPECT_EQ(count["CODESIGN_EPISODE"], rows(logged / "episodes.csv"));
  EXPECT_EQ(count["CODESIGN_SIM_STEP"],
            rows(logged / "eval" / "best_trace.csv") + rows(logged / "eval" / "runner_up_trace.csv"));
  EXPECT_GT(count["CODESIGN_SIM_STEP"], 2);
  // Training environment 0, the end of every 2nd decision: it takes n_steps decisions in each of
  // the 6 iterations.
  const LoopConfig& lc = test::tiny_run().loop;
  EXPECT_EQ(count["CODESIGN_TRAIN_STEP"], 6 * lc.ppo.n_steps / 2);
  EXPECT_GT(count["CODESIGN_TRAIN_STEP"], 0);
  // Each is stamped with the timestep at the start of its iteration and carries environment 0's
  // design of that iteration (sampled.csv: k, t after the iteration, i, j).
  std::map<std::int64_t, int> design_of_env0;  // start timestep -> j
  const io::CsvTable sampled = io::read_csv((logged / "sampled.csv").string());
  const std::int64_t per_iteration = 4 * lc.ppo.n_steps;
  for (std::size_t r = 0; r < sampled.rows(); ++r)
    if (sampled.integer(r, sampled.column("i")) == 0)
      design_of_env0[sampled.integer(r, sampled.column("t")) - per_iteration] =
          static_cast<int>(sampled.integer(r, sampled.column("j")));
  for (const codesign_lcm::sim_step_t& m : training) {
    ASSERT_EQ(design_of_env0.count(m.timestep), 1u) << m.timestep;
    EXPECT_EQ(m.design, design_of_env0[m.timestep]) << m.timestep;
    EXPECT_GT(m.t_s, 0.0);  // a step of the episode, not the settled state
    EXPECT_GE(m.decision, 0);
    EXPECT_LT(m.decision, lc.ppo.n_steps);
  }
  // The run counts what it published: every message of the log.
  int total = 0;
  for (const auto& [channel, n] : count) total += n;
  EXPECT_EQ(on.telemetry_messages, total);
  EXPECT_GT(on.telemetry_s, 0.0);
  EXPECT_LT(on.telemetry_s, on.wall_s);
}

// With the recurrent policy the log also holds its memory: one message per decision of training
// environment 0, each with that environment's design, the decision's index in the episode and
// hidden states of the configured size whose norms are the ones stated.
TEST(Run, RecurrentRunPublishesItsMemory) {
  RunSettings s = test::tiny_run();
  s.loop.ppo.policy = rl::PolicyKind::Gru;
  s.loop.ppo.gru_hidden = 8;
  s.loop.codesign.total_timesteps = 40;  // 2 iterations of 4 x 5
  s.loop.codesign.distribution.exploration_end = 20;
  s.loop.codesign.distribution.exploitation_start = 30;
  const fs::path d = test_files::fresh_dir("run_tel_gru");
  fs::create_directories(d);
  const fs::path log = d / "telemetry.lcm";
  RunOptions o = opts(d);
  o.telemetry_url = "file://" + log.string() + "?mode=w";
  ASSERT_TRUE(run_codesign(s, o).completed);

  std::vector<codesign_lcm::policy_memory_t> memory;
  // The decision indices environment 0's episodes give, per iteration: 0 .. decisions − 1 for
  // each of its episodes in turn (one ends early when, e.g., the whisker loses the plate).
  std::vector<std::vector<int>> expected(2);
  lcm_eventlog_t* in = lcm_eventlog_create(log.c_str(), "r");
  ASSERT_NE(in, nullptr);
  while (lcm_eventlog_event_t* e = lcm_eventlog_read_next_event(in)) {
    const std::string channel(e->channel, e->channellen);
    if (channel == io::kPolicyMemoryChannel) {
      codesign_lcm::policy_memory_t m;
      EXPECT_EQ(m.decode(e->data, 0, e->datalen), e->datalen);
      memory.push_back(m);
    } else if (channel == io::kEpisodeChannel) {
      codesign_lcm::episode_t m;
      EXPECT_EQ(m.decode(e->data, 0, e->datalen), e->datalen);
      if (m.env == 0 && m.iteration >= 0 && m.iteration < 2)
        for (int i = 0; i < m.decisions; ++i) expected[static_cast<std::size_t>(m.iteration)].push_back(i);
    }
    lcm_eventlog_free_event(e);
  }
  lcm_eventlog_destroy(in);
  const int n_steps = s.loop.ppo.n_steps;
  ASSERT_EQ(static_cast<int>(memory.size()), 2 * n_steps);
  for (const auto& e : expected) ASSERT_EQ(static_cast<int>(e.size()), n_steps);
  const io::CsvTable sampled = io::read_csv((d / "sampled.csv").string());
  for (int k = 0; k < 2; ++k) {
    int design = -1;  // environment 0's design in iteration k (sampled.csv: k, t, i, j)
    for (std::size_t r = 0; r < sampled.rows(); ++r)
      if (sampled.integer(r, sampled.column("k")) == k && sampled.integer(r, sampled.column("i")) == 0)
        design = static_cast<int>(sampled.integer(r, sampled.column("j")));
    for (int step = 0; step < n_steps; ++step) {
      const codesign_lcm::policy_memory_t& m = memory[static_cast<std::size_t>(k * n_steps + step)];
      EXPECT_EQ(m.timestep, static_cast<std::int64_t>(k) * 4 * n_steps);
      EXPECT_EQ(m.decision, expected[static_cast<std::size_t>(k)][static_cast<std::size_t>(step)]) << k << " " << step;
      EXPECT_EQ(m.design, design);
      ASSERT_EQ(m.units, 8);
      ASSERT_EQ(m.actor_h.size(), 8u);
      ASSERT_EQ(m.critic_h.size(), 8u);
      double a2 = 0.0, c2 = 0.0;
      for (int u = 0; u < 8; ++u) {
        a2 += static_cast<double>(m.actor_h[u]) * m.actor_h[u];
        c2 += static_cast<double>(m.critic_h[u]) * m.critic_h[u];
        EXPECT_LT(std::abs(m.actor_h[u]), 1.0f);  // a GRU state stays inside (-1, 1)
      }
      EXPECT_NEAR(m.actor_norm, std::sqrt(a2), 1e-12 * (1.0 + m.actor_norm));
      EXPECT_NEAR(m.critic_norm, std::sqrt(c2), 1e-12 * (1.0 + m.critic_norm));
      EXPECT_GT(m.actor_norm, 0.0);
    }
  }
}

}  // namespace
