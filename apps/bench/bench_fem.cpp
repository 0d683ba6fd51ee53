// `codesign bench fem [--config run.toml] [--design J] [--steps N]`
//
// Times the simulator step of one design in contact, in one run:
//  * the fast step (stored, rotation-aware factorisation preconditioning a matrix-free CG with
//    active-set contact) — the one used in training;
//  * the exact step (full assembly + CHOLMOD numeric refactorisation + exact contact LCP every
//    step);
// over the same episode: quasi-static settling, then N steps of the plate oscillation while θ
// follows a fixed, action-like schedule (θ target 1° + 1°·sin(0.37 d) for decision d = k / 5, each
// change spread over 5 steps; with --turn-deg D instead D·sin(1.1 d), turns of up to about
// 1.04·D per decision, like those of a policy that is still exploring). Prints the median / mean /
// 90th-percentile step times, the speed-up, and the difference between the two trajectories:
// max |ΔF| relative to max F, max per-step relative ΔF where F > 10 % of max F, and max tip
// position difference.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "base/peak_memory.hpp"
#include "base/thread_cpu_seconds.hpp"
#include "commands.hpp"
#include "run/run_config.hpp"

namespace codesign::app {

namespace {

struct BenchFemOptions {
  std::string config;
  int design = -1;
  int steps = 250;
  double turn_deg = -1.0;  // < 0: the gentle default schedule
};

struct Trace {
  std::vector<double> seconds, cpu_seconds, force_mN;
  std::vector<Eigen::Vector3d> tip;
  int iterations = 0, refactorisations = 0;
  std::string failure;
  // Heap the simulator holds [MiB]: new, after the episode, after drop_stored_factors().
  double heap_new = 0.0, heap_used = 0.0, heap_dropped = 0.0;
};

// θ target of decision d: the gentle default schedule, or turn_deg·sin(1.1 d); and the same
// schedule in words, for the header line.
double theta_target(int d, double turn_deg) {
  const double theta_max = std::numbers::pi / 18.0;
  if (turn_deg < 0.0) return 0.1 * theta_max * (1.0 + std::sin(0.37 * d));
  return turn_deg * std::numbers::pi / 180.0 * std::sin(1.1 * d);
}
std::string theta_schedule_text(double turn_deg) {
  if (turn_deg < 0.0) return "1 + sin(0.37 d) deg";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g sin(1.1 d) deg", turn_deg);
  return buf;
}

Trace run_episode(const std::shared_ptr<const fem::Model>& model, const run::RunConfig& s, fem::StepMethod method,
                  int steps, double turn_deg) {
  fem::SolverConfig so = s.solver;
  so.method = method;
  const double heap0 = heap_in_use_mib();
  fem::Simulator sim(model, s.scene, so);
  Trace tr;
  tr.heap_new = heap_in_use_mib() - heap0;
  sim.set_pressures_kPa(s.scenario.pressures_kPa[0], s.scenario.pressures_kPa[1]);
  fem::StepResult r = sim.settle();
  if (!r.ok()) {
    tr.failure = "settle: " + r.reason;
    return tr;
  }
  for (int k = 0; k < steps; ++k) {
    if (k % 5 == 0) sim.set_base_angle_target(theta_target(k / 5, turn_deg), 5);
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = thread_cpu_seconds();
    r = sim.step();
    tr.cpu_seconds.push_back(thread_cpu_seconds() - c0);
    tr.seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    if (!r.ok()) {
      tr.failure = "step " + std::to_string(k) + ": " + r.reason;
      return tr;
    }
    tr.iterations += r.iterations;
    tr.refactorisations += r.refactorised;
    tr.force_mN.push_back(sim.sensors().contact_force_mN);
    tr.tip.push_back(sim.sensors().tip_position_mm);
  }
  tr.heap_used = heap_in_use_mib() - heap0;
  sim.drop_stored_factors();
  tr.heap_dropped = heap_in_use_mib() - heap0;
  return tr;
}

double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * v.size()))];
}

double mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return s / v.size();
}

int run_bench(const BenchFemOptions& opt) {
  run::RunConfig s = run::read_run_config(opt.config);
  const int design = opt.design >= 0 ? opt.design : s.scenario.design;
  const double heap0 = heap_in_use_mib();
  const auto model = fem::build_whisker_model(design, s.spec);
  const double heap_model = heap_in_use_mib() - heap0;
  std::printf("bench fem: design %d, %d nodes, %zu tets, %d free DOFs, %zu fibre springs, dt = %g s, %d steps\n",
              design, model->node_count(), model->mesh.tets.size(),
              3 * (model->node_count() - static_cast<int>(model->base_nodes.size())), model->fibres.size(),
              s.solver.dt_s, opt.steps);
  std::printf("  theta target %s per decision d (5 steps each); fast_stop %s, fast_tolerance %g, refactorise after %d CG "
              "iterations\n",
              theta_schedule_text(opt.turn_deg).c_str(),
              name_of(fem::kFastStopNames, s.solver.fast_stop).data(), s.solver.fast_tolerance,
              s.solver.fast_refactor_iterations);
  const Trace fast = run_episode(model, s, fem::StepMethod::Fast, opt.steps, opt.turn_deg);
  const Trace exact = run_episode(model, s, fem::StepMethod::Exact, opt.steps, opt.turn_deg);
  if (!fast.failure.empty() || !exact.failure.empty()) {
    std::fprintf(stderr, "bench fem: failed: fast [%s] exact [%s]\n", fast.failure.c_str(), exact.failure.c_str());
    return 3;
  }
  double fmax = 0.0, dfmax = 0.0, rel_max = 0.0, tip_max = 0.0, fmin = 1e300;
  for (double f : exact.force_mN) fmax = std::max(fmax, f), fmin = std::min(fmin, f);
  for (std::size_t k = 0; k < exact.force_mN.size(); ++k) {
    const double d = std::abs(fast.force_mN[k] - exact.force_mN[k]);
    dfmax = std::max(dfmax, d);
    if (exact.force_mN[k] > 0.1 * fmax) rel_max = std::max(rel_max, d / exact.force_mN[k]);
    tip_max = std::max(tip_max, (fast.tip[k] - exact.tip[k]).norm());
  }
  const double fm = quantile(fast.seconds, 0.5), em = quantile(exact.seconds, 0.5);
  std::printf("  F over the episode (exact): %.3f .. %.3f mN\n", fmin, fmax);
  std::printf("  fast step : median %.3f ms, mean %.3f ms, p90 %.3f ms; %.2f CG iterations/step, %d refactorisations\n",
              1e3 * fm, 1e3 * mean(fast.seconds), 1e3 * quantile(fast.seconds, 0.9),
              double(fast.iterations) / opt.steps, fast.refactorisations);
  std::printf("  exact step: median %.3f ms, mean %.3f ms, p90 %.3f ms (assembly + CHOLMOD refactorisation every step)\n",
              1e3 * em, 1e3 * mean(exact.seconds), 1e3 * quantile(exact.seconds, 0.9));
  std::printf("  speed-up  : %.1fx (median), %.1fx (mean)\n", em / fm, mean(exact.seconds) / mean(fast.seconds));
  const double fc = quantile(fast.cpu_seconds, 0.5), ec = quantile(exact.cpu_seconds, 0.5);
  std::printf("  thread CPU time (excludes time given to other processes): fast median %.3f ms, mean %.3f ms; "
              "exact median %.3f ms, mean %.3f ms; speed-up %.1fx (median)\n",
              1e3 * fc, 1e3 * mean(fast.cpu_seconds), 1e3 * ec, 1e3 * mean(exact.cpu_seconds), ec / fc);
  std::printf("  fast vs exact: max |dF| = %.3g mN = %.3g %% of max F; max per-step |dF|/F (F > 10%% max) = %.3g %%; "
              "max tip distance = %.3g mm\n",
              dfmax, 100.0 * dfmax / fmax, 100.0 * rel_max, tip_max);
  std::printf("  goals (wall-clock medians): median <= 1 ms [%s], >= 10x faster [%s], F within 1 %% [%s]\n",
              fm <= 1e-3 ? "met" : "NOT met", em / fm >= 10.0 ? "met" : "NOT met", rel_max <= 0.01 ? "met" : "NOT met");
  // What a run's simulator pool holds per design and per simulator (docs/memory.md).
  std::printf("  memory (heap in use): model %.2f MiB; fast-step simulator new %.2f MiB, after the episode %.2f MiB, "
              "idle in the pool (drop_stored_factors) %.2f MiB; peak resident %.0f MiB\n",
              heap_model, fast.heap_new, fast.heap_used, fast.heap_dropped, peak_resident_mib());
  return 0;
}

}  // namespace

void add_bench_fem_command(CLI::App& bench, Runner& run) {
  auto opt = std::make_shared<BenchFemOptions>();
  CLI::App* cmd = bench.add_subcommand("fem", "FEM step: fast vs exact time and accuracy on one design in contact");
  cmd->add_option("--config", opt->config, "run config (TOML); default: built-in defaults");
  cmd->add_option("--design", opt->design, "design index 0..109 (default [sim].design = 21)")->check(CLI::Range(0, 109));
  cmd->add_option("--steps", opt->steps, "steps of the episode (default 250)")->check(CLI::Range(10, 100000));
  cmd->add_option("--turn-deg", opt->turn_deg,
                  "theta target D*sin(1.1 d) per decision d, policy-like turns (default: 1 + sin(0.37 d) deg)")
      ->check(CLI::Range(0.0, 10.0));
  cmd->callback([opt, &run] { run = [opt] { return run_bench(*opt); }; });
}

}  // namespace codesign::app
