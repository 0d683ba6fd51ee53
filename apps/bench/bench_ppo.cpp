// `codesign bench ppo`: wall time of one PPO iteration at the paper's sizes, on one thread.
//
// One iteration = the policy/value forward passes of a rollout (40 envs x 50 steps = 2000
// samples of synthetic observations, obs dim 6, action dim 1; no environment is stepped), GAE,
// and the PPO update (10 epochs over minibatches of 256) with actor and critic [512, 512, 512].
// target_kl is disabled so all 10 epochs run (the cost ceiling); the run with target_kl 0.02 is
// printed too but depends on how soon the KL limit trips.
// GFLOP/s counts only the GEMMs of the forward and backward passes (2 flops per multiply-add).
// The iteration runs with the matrix-product precision a training run would use ("auto": bf16
// operands with float32 sums where the CPU has AVX-512 BF16, else float32; --precision
// overrides). Baselines in the same run: the same iteration with float32 products (rl::sgemm)
// and with Eigen's products only; on the dominant GEMM shape, Eigen, rl::sgemm, rl::gemm_bf16
// and a textbook triple loop; and one minibatch pass in float64 (Eigen). Beside it, the same
// iteration with the recurrent policy (ppo.policy = "gru", --gru-hidden units), and the update of
// both policies with the actor's and the critic's passes side by side on 2 threads against 1
// (wall time; needs two idle cores to mean anything).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <Eigen/Core>

#if defined(__AVX512BF16__)
#include <immintrin.h>
#endif

#include "base/thread_cpu_seconds.hpp"
#include "commands.hpp"
#include "io/config/gym_config.hpp"
#include "minibatch_timing.hpp"
#include "rl/gemm.hpp"
#include "rl/ppo.hpp"
#include "rl/recurrent_ppo.hpp"

namespace codesign::app {

namespace {

using Clock = std::chrono::steady_clock;

// Measured single-core fp32 FMA peak: 16 independent chains of fused multiply-adds on the
// widest vectors of the build (16 lanes with AVX-512, 8 with AVX, else 4; enough chains to cover
// FMA latency x throughput on current x86 cores), no memory traffic.
#if defined(__AVX512F__)
constexpr int kPeakLanes = 16;
#elif defined(__AVX__)
constexpr int kPeakLanes = 8;
#else
constexpr int kPeakLanes = 4;
#endif

__attribute__((noinline)) double peak_fma_gflops() {
  using V = float __attribute__((vector_size(4 * kPeakLanes)));
  constexpr int kChains = 16;
  V acc[kChains];
  for (int c = 0; c < kChains; ++c)
    for (int l = 0; l < kPeakLanes; ++l) acc[c][l] = 1.0f + 1e-3f * float(c + l);
  V mul, add;
  for (int l = 0; l < kPeakLanes; ++l) {
    mul[l] = 0.999999f;
    add[l] = 1e-7f;
  }
  const long iters = 20'000'000;
  const double t0 = thread_cpu_seconds();
  for (long i = 0; i < iters; ++i) {
#pragma GCC unroll 16
    for (int c = 0; c < kChains; ++c) acc[c] = acc[c] * mul + add;
    asm volatile("" : "+x"(mul));  // keep the loop from being folded
  }
  const double t = thread_cpu_seconds() - t0;
  float sink = 0;
  for (int c = 0; c < kChains; ++c) sink += acc[c][0];
  if (!std::isfinite(sink)) std::printf("(peak loop overflowed)\n");
  return 2.0 * kPeakLanes * kChains * static_cast<double>(iters) / t * 1e-9;
}

// Measured single-core bf16 dot-product peak (vdpbf16ps: 32 multiply-adds per instruction);
// 0 when the build has no AVX-512 BF16.
__attribute__((noinline)) double peak_bf16_gflops() {
#if defined(__AVX512BF16__)
  constexpr int kChains = 16;
  __m512 acc[kChains];
  for (int c = 0; c < kChains; ++c) acc[c] = _mm512_set1_ps(1e-3f * float(c));
  const __m512bh a = (__m512bh)_mm512_set1_epi32(0x3f803f80);  // (1, 1)
  const __m512bh b = (__m512bh)_mm512_set1_epi32(0x33803380);  // (2^-24, 2^-24)
  const long iters = 20'000'000;
  const double t0 = thread_cpu_seconds();
  for (long i = 0; i < iters; ++i) {
#pragma GCC unroll 16
    for (int c = 0; c < kChains; ++c) acc[c] = _mm512_dpbf16_ps(acc[c], a, b);
    asm volatile("" ::"v"(a));  // keep the loop from being folded
  }
  const double t = thread_cpu_seconds() - t0;
  float sink = 0;
  for (int c = 0; c < kChains; ++c) sink += acc[c][0];
  if (!std::isfinite(sink)) std::printf("(bf16 peak loop overflowed)\n");
  return 2.0 * 32 * kChains * static_cast<double>(iters) / t * 1e-9;
#else
  return 0.0;
#endif
}

struct BenchOptions {
  int reps = 5;
  int n_envs = 40;
  int n_steps = 50;
  int hidden = 512;
  bool with_kl = true;
  int gru_hidden = 64;  // the recurrent policy's iteration beside the MLP's; 0: skipped
  bool update_threads = true;  // the update on 2 threads (actor | critic) against 1
  std::string precision = "auto";  // auto | float32 | bf16
};

const char* describe(rl::MatmulPrecision p) {
  return p == rl::MatmulPrecision::BFloat16 ? "bf16 operands, float32 sums" : "float32";
}

struct IterationTimes {
  double rollout = 0, gae = 0, update = 0;
  double cpu = 0;  // thread CPU time of the whole iteration
  double total() const { return rollout + gae + update; }
  rl::PpoStats stats;
};

// One synthetic iteration: forward passes of the rollout, GAE, PPO update.
IterationTimes run_iteration(rl::ActorCritic& model, rl::Adam& adam, const rl::PpoConfig& cfg,
                             int n_envs, rl::Rng& rng, rl::ThreadPool* pool = nullptr) {
  IterationTimes t;
  rl::RolloutBuffer buffer(cfg.n_steps, n_envs, model.obs_dim(), model.act_dim());
  Eigen::MatrixXf obs(model.obs_dim(), n_envs);
  Eigen::RowVectorXf starts = Eigen::RowVectorXf::Ones(n_envs);
  rl::ActorCritic::InferenceCache inference;  // as the trainer: packed weights reused by 50 steps
  const double cpu0 = thread_cpu_seconds();
  auto t0 = Clock::now();
  for (int s = 0; s < cfg.n_steps; ++s) {
    for (Eigen::Index i = 0; i < obs.size(); ++i) obs(i) = static_cast<float>(rng.normal());
    const auto out = model.act(obs, rng, inference);
    Eigen::RowVectorXf rewards(n_envs);
    for (int e = 0; e < n_envs; ++e) rewards(e) = static_cast<float>(rng.normal());
    buffer.add(obs, out.actions, rewards, starts, out.values, out.log_probs);
    starts.setZero();
  }
  const Eigen::RowVectorXf last_values = model.value(obs, inference);
  t.rollout = seconds_since(t0);
  t0 = Clock::now();
  buffer.compute_returns_and_advantage(last_values, Eigen::RowVectorXf::Zero(n_envs), cfg.gamma,
                                       cfg.gae_lambda);
  t.gae = seconds_since(t0);
  t0 = Clock::now();
  t.stats = rl::ppo_update(model, adam, buffer, cfg, 0, rng, true, pool);
  t.update = seconds_since(t0);
  t.cpu = thread_cpu_seconds() - cpu0;
  return t;
}

// The same iteration with the recurrent policy (ppo.policy = "gru"): one GRU step per env and
// decision in the rollout (episode starts at step 0), then recurrent_ppo_update over whole env
// columns (batch_size / n_steps columns per minibatch).
IterationTimes run_recurrent_iteration(rl::RecurrentActorCritic& model, rl::Adam& adam, const rl::PpoConfig& cfg,
                                       int n_envs, rl::Rng& rng, rl::ThreadPool* pool = nullptr) {
  IterationTimes t;
  rl::RolloutBuffer buffer(cfg.n_steps, n_envs, model.obs_dim(), model.act_dim());
  Eigen::MatrixXf obs(model.obs_dim(), n_envs);
  Eigen::RowVectorXf starts = Eigen::RowVectorXf::Ones(n_envs);
  rl::RecurrentState state = model.zero_state(n_envs);
  const rl::RecurrentState initial = state;
  const double cpu0 = thread_cpu_seconds();
  auto t0 = Clock::now();
  for (int s = 0; s < cfg.n_steps; ++s) {
    for (Eigen::Index i = 0; i < obs.size(); ++i) obs(i) = static_cast<float>(rng.normal());
    const auto out = model.act(obs, starts, state, rng);
    Eigen::RowVectorXf rewards(n_envs);
    for (int e = 0; e < n_envs; ++e) rewards(e) = static_cast<float>(rng.normal());
    buffer.add(obs, out.actions, rewards, starts, out.values, out.log_probs);
    starts.setZero();
  }
  const Eigen::RowVectorXf last_values = model.value_step(obs, state.critic);
  t.rollout = seconds_since(t0);
  t0 = Clock::now();
  buffer.compute_returns_and_advantage(last_values, Eigen::RowVectorXf::Zero(n_envs), cfg.gamma, cfg.gae_lambda);
  t.gae = seconds_since(t0);
  t0 = Clock::now();
  t.stats = rl::recurrent_ppo_update(model, adam, buffer, initial, cfg, 0, rng, pool);
  t.update = seconds_since(t0);
  t.cpu = thread_cpu_seconds() - cpu0;
  return t;
}

// GEMM flops of one iteration given the minibatches actually processed.
double iteration_flops(const rl::ActorCritic& m, int samples, int epochs_of_full_passes) {
  const double rollout = (m.actor().forward_flops(samples) + m.critic().forward_flops(samples));
  const double per_sample_update = (m.actor().forward_flops(1) + m.actor().backward_flops(1) +
                                    m.critic().forward_flops(1) + m.critic().backward_flops(1));
  return rollout + per_sample_update * samples * epochs_of_full_passes;
}

// Textbook C = A B, i-j-k loops with a dot product over k (column-major storage).
void naive_gemm(const Eigen::MatrixXf& a, const Eigen::MatrixXf& b, Eigen::MatrixXf& c) {
  const Eigen::Index m = a.rows(), k = a.cols(), n = b.cols();
  for (Eigen::Index i = 0; i < m; ++i)
    for (Eigen::Index j = 0; j < n; ++j) {
      float s = 0;
      for (Eigen::Index p = 0; p < k; ++p) s += a(i, p) * b(p, j);
      c(i, j) = s;
    }
}

template <class S>
double minibatch_pass_seconds(int hidden, int batch, int reps) {
  rl::Rng rng(1);
  rl::ActorCriticT<S> model(6, 1, {hidden, hidden, hidden}, {hidden, hidden, hidden});
  model.init_orthogonal(rng);
  rl::PpoMinibatchT<S> mb;
  mb.obs.resize(6, batch);
  for (Eigen::Index i = 0; i < mb.obs.size(); ++i) mb.obs(i) = static_cast<S>(rng.normal());
  const auto a = model.act(mb.obs, rng);
  mb.actions = a.actions;
  mb.old_log_prob = a.log_probs;
  mb.advantages = a.values;
  mb.returns = a.values.array() + S(1);
  return minibatch_loss_seconds<S>(model, mb, {0.2, 0.01, 0.6, true}, 0, reps);
}

// Median times of iterations.
struct Measured {
  double wall = 0, cpu = 0, rollout = 0, update = 0;
};

// The medians of `reps` calls of `iterate`, each returning its IterationTimes.
template <class Iterate>
Measured median_times(int reps, Iterate&& iterate) {
  std::vector<double> total, cpu, rollout, update;
  for (int r = 0; r < reps; ++r) {
    const IterationTimes times = iterate();
    total.push_back(times.total());
    cpu.push_back(times.cpu);
    rollout.push_back(times.rollout);
    update.push_back(times.update);
  }
  return {median(total), median(cpu), median(rollout), median(update)};
}

// Median times of `reps` iterations (after one warm-up) of a fresh model with the given
// product precision / GEMM choice.
Measured measure(const rl::PpoConfig& cfg, int n_envs, int reps, rl::MatmulPrecision precision,
                 bool fast_gemm) {
  rl::Rng rng(2024);
  rl::ActorCritic model(6, 1, cfg.actor_hidden, cfg.critic_hidden);
  model.init_orthogonal(rng);
  model.set_fast_gemm(fast_gemm);
  model.set_matmul_precision(precision);
  rl::Adam adam = rl::make_adam(cfg);
  run_iteration(model, adam, cfg, n_envs, rng);  // warm-up (allocations, page faults)
  return median_times(reps, [&] { return run_iteration(model, adam, cfg, n_envs, rng); });
}

// What the parts of the benchmark share: the options, the PPO config at their sizes with
// target_kl off (all epochs run), the matrix products' precision, the repetitions of the
// comparisons, and the measured iteration they are compared with with its GEMM flops.
struct PpoBench {
  const BenchOptions& options;
  rl::PpoConfig cfg;
  rl::MatmulPrecision precision;
  int base_reps;
  double flops;
  Measured main_run;
};

rl::PpoConfig bench_config(const BenchOptions& options) {
  rl::PpoConfig cfg = rl::paper_ppo_config();
  cfg.n_steps = options.n_steps;
  cfg.actor_hidden = cfg.critic_hidden = {options.hidden, options.hidden, options.hidden};
  cfg.target_kl.reset();
  return cfg;
}

void print_header(const PpoBench& bench) {
  const BenchOptions& options = bench.options;
  const rl::PpoConfig& cfg = bench.cfg;
  const int samples = options.n_envs * options.n_steps;
  std::printf("PPO iteration benchmark (one thread, Eigen %d.%d.%d, SIMD: %s)\n",
              EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION,
              Eigen::SimdInstructionSetsInUse());
  std::printf("  %d envs x %d steps = %d samples, obs 6, act 1, actor/critic [%d, %d, %d], "
              "batch %d, %d epochs\n",
              options.n_envs, options.n_steps, samples, options.hidden, options.hidden, options.hidden,
              cfg.batch_size, cfg.n_epochs);
  std::printf("  matrix products: %s (--precision %s; training's default is auto)\n",
              describe(bench.precision), options.precision.c_str());
  const rl::ActorCritic probe(6, 1, cfg.actor_hidden, cfg.critic_hidden);
  std::printf("  parameters: %lld (actor %lld, critic %lld, log_std %lld)\n",
              static_cast<long long>(probe.num_params()),
              static_cast<long long>(probe.actor().num_params()),
              static_cast<long long>(probe.critic().num_params()),
              static_cast<long long>(probe.log_std().size()));
}

// The iteration at the measured precision, all epochs: its median times and GEMM rate, against
// the goal of 0.8 s.
void time_main_iteration(PpoBench& bench) {
  const BenchOptions& options = bench.options;
  const rl::PpoConfig& cfg = bench.cfg;
  const rl::ActorCritic counter(6, 1, cfg.actor_hidden, cfg.critic_hidden);
  bench.flops = iteration_flops(counter, options.n_envs * options.n_steps, cfg.n_epochs);
  bench.main_run = measure(cfg, options.n_envs, options.reps, bench.precision, true);
  const Measured& main_run = bench.main_run;
  const double gflop = bench.flops * 1e-9;
  std::printf("\n  target_kl off (all %d epochs), median of %d:\n", cfg.n_epochs, options.reps);
  std::printf("    iteration      %.3f s   (rollout forwards %.3f s, update %.3f s)\n", main_run.wall,
              main_run.rollout, main_run.update);
  std::printf("    thread CPU     %.3f s\n", main_run.cpu);
  std::printf("    GEMM work      %.1f GFLOP  ->  %.1f GFLOP/s (wall), %.1f GFLOP/s (CPU time)\n",
              gflop, gflop / main_run.wall, gflop / main_run.cpu);
  std::printf("    goal 0.8 s:    %s (needs %.0f GFLOP/s)\n", main_run.wall <= 0.8 ? "met" : "NOT met",
              gflop / 0.8);
}

// One baseline: the same iteration in float32 with or without the own GEMM kernel.
void print_float32_baseline(const PpoBench& bench, bool fast_gemm, const char* what, const char* winner) {
  const Measured baseline =
      measure(bench.cfg, bench.options.n_envs, bench.base_reps, rl::MatmulPrecision::Float32, fast_gemm);
  std::printf("\n  baseline, same iteration with %s, median of %d:\n", what, bench.base_reps);
  std::printf("    iteration      %.3f s wall, %.3f s CPU -> %.1f GFLOP/s (CPU time)\n", baseline.wall,
              baseline.cpu, bench.flops * 1e-9 / baseline.cpu);
  std::printf("    %s %.2fx faster (CPU time; %.2fx wall)\n", winner, baseline.cpu / bench.main_run.cpu,
              baseline.wall / bench.main_run.wall);
}

void print_float32_baselines(const PpoBench& bench) {
  if (bench.precision == rl::MatmulPrecision::BFloat16)
    print_float32_baseline(bench, true, "float32 products (rl::sgemm)", "bf16 products are");
  print_float32_baseline(bench, false, "Eigen's float32 GEMM only", "the measured configuration is");
}

// The recurrent policy at the same sizes, target_kl off: the GRUs' products are small
// (gru_hidden x 6 and gru_hidden x gru_hidden per step), so they run in float32 with Eigen;
// the MLP heads use the measured precision.
void time_recurrent_iteration(const PpoBench& bench) {
  const BenchOptions& options = bench.options;
  const rl::PpoConfig& cfg = bench.cfg;
  rl::Rng rng(2024);
  rl::RecurrentActorCritic gru(6, 1, options.gru_hidden, cfg.actor_hidden, cfg.critic_hidden);
  gru.init(rng);
  gru.set_matmul_precision(bench.precision);
  rl::Adam adam = rl::make_adam(cfg);
  run_recurrent_iteration(gru, adam, cfg, options.n_envs, rng);  // warm-up
  const Measured times =
      median_times(bench.base_reps, [&] { return run_recurrent_iteration(gru, adam, cfg, options.n_envs, rng); });
  std::printf("\n  recurrent policy (ppo.policy = \"gru\", GRU %d before each MLP; %d envs per minibatch), "
              "target_kl off, median of %d:\n",
              options.gru_hidden, rl::sequences_per_minibatch(cfg, options.n_envs), bench.base_reps);
  std::printf("    iteration      %.3f s wall, %.3f s CPU (rollout forwards %.3f s, update %.3f s)\n",
              times.wall, times.cpu, times.rollout, times.update);
  std::printf("    vs the MLP     %.2fx its CPU time; parameters %lld (GRUs %lld)\n", times.cpu / bench.main_run.cpu,
              static_cast<long long>(gru.num_params()),
              static_cast<long long>(gru.actor_gru().num_params() + gru.critic_gru().num_params()));
}

// The update with the actor's and the critic's passes side by side on two threads (as a
// co-design run does on its rollout threads), against one thread, from the same state and
// seeds: wall times (a thread's CPU time no longer covers the work) and whether the trained
// parameters are the same to the bit. `make_model` gives a fresh model, `iterate` runs one
// iteration of it (on the pool, or on one thread if none).
template <class MakeModel, class Iterate>
void compare_update_threads(const PpoBench& bench, MakeModel make_model, Iterate iterate, const char* what) {
  const int reps = bench.base_reps;
  auto on_one = make_model(), on_two = make_model();
  rl::Adam adam_one = rl::make_adam(bench.cfg), adam_two = rl::make_adam(bench.cfg);
  rl::ThreadPool pool(2);
  rl::Rng warmup_one(99), warmup_two(99);
  iterate(on_one, adam_one, warmup_one, nullptr);  // warm-up
  iterate(on_two, adam_two, warmup_two, &pool);
  std::vector<double> update_one, update_two;
  for (int r = 0; r < reps; ++r) {
    rl::Rng rng_one(100 + r), rng_two(100 + r);
    update_one.push_back(iterate(on_one, adam_one, rng_one, nullptr).update);
    update_two.push_back(iterate(on_two, adam_two, rng_two, &pool).update);
  }
  const bool same =
      on_one.actor().params() == on_two.actor().params() && on_one.critic().params() == on_two.critic().params();
  std::printf("\n  %s: update with actor and critic side by side on 2 threads, median of %d (wall):\n", what,
              reps);
  std::printf("    update         %.3f s on 2 threads vs %.3f s on 1 -> %.2fx faster; parameters after %d "
              "iterations %s\n",
              median(update_two), median(update_one), median(update_one) / median(update_two), reps + 1,
              same ? "identical to the bit" : "DIFFER (a bug)");
}

void time_update_threads(const PpoBench& bench) {
  const BenchOptions& options = bench.options;
  const rl::PpoConfig& cfg = bench.cfg;
  compare_update_threads(
      bench,
      [&] {
        rl::Rng init(2024);
        rl::ActorCritic model(6, 1, cfg.actor_hidden, cfg.critic_hidden);
        model.init_orthogonal(init);
        model.set_matmul_precision(bench.precision);
        return model;
      },
      [&](rl::ActorCritic& model, rl::Adam& adam, rl::Rng& rng, rl::ThreadPool* pool) {
        return run_iteration(model, adam, cfg, options.n_envs, rng, pool);
      },
      "MLP");
  if (options.gru_hidden > 0)
    compare_update_threads(
        bench,
        [&] {
          rl::Rng init(2024);
          rl::RecurrentActorCritic model(6, 1, options.gru_hidden, cfg.actor_hidden, cfg.critic_hidden);
          model.init(init);
          model.set_matmul_precision(bench.precision);
          return model;
        },
        [&](rl::RecurrentActorCritic& model, rl::Adam& adam, rl::Rng& rng, rl::ThreadPool* pool) {
          return run_recurrent_iteration(model, adam, cfg, options.n_envs, rng, pool);
        },
        "GRU");
}

// One iteration of a fresh policy with target_kl 0.02: how many epochs run before the KL limit trips.
void time_kl_limited_iteration(const PpoBench& bench) {
  rl::PpoConfig cfg = bench.cfg;
  cfg.target_kl = 0.02;
  rl::Rng rng_kl(7);
  rl::ActorCritic fresh(6, 1, cfg.actor_hidden, cfg.critic_hidden);
  fresh.init_orthogonal(rng_kl);
  fresh.set_matmul_precision(bench.precision);
  rl::Adam adam_kl = rl::make_adam(cfg);
  const IterationTimes times = run_iteration(fresh, adam_kl, cfg, bench.options.n_envs, rng_kl);
  std::printf("\n  target_kl 0.02 (fresh policy, synthetic rewards), one run:\n");
  std::printf("    iteration      %.3f s   (%d epochs started, %d minibatches applied%s)\n",
              times.total(), times.stats.epochs_done, times.stats.minibatches_applied,
              times.stats.early_stopped ? ", KL early stop" : "");
}

// Seconds of each timed product of one GEMM shape; sgemm and bf16 are empty where the build or
// CPU lacks the kernel.
struct GemmTimes {
  std::vector<double> eigen, sgemm, bf16, naive;
  bool naive_matches = true;  // the triple loop's product equals Eigen's (a check of the timing)
};

// Times C = A B for A rows x inner and B inner x cols of random values with Eigen, rl::sgemm,
// rl::gemm_bf16 and the textbook loops.
GemmTimes time_gemm_kernels(int rows, int inner, int cols) {
  GemmTimes times;
  Eigen::MatrixXf lhs = Eigen::MatrixXf::Random(rows, inner), rhs = Eigen::MatrixXf::Random(inner, cols);
  Eigen::MatrixXf product(rows, cols);
  for (int r = 0; r < 5; ++r) {
    auto t0 = Clock::now();
    product.noalias() = lhs * rhs;
    times.eigen.push_back(seconds_since(t0));
  }
  rl::GemmWorkspace ws;
  Eigen::MatrixXf product_sgemm(rows, cols);
  for (int r = 0; r < (rl::fast_gemm_available() ? 5 : 0); ++r) {
    auto t0 = Clock::now();
    rl::sgemm(false, false, rows, cols, inner, lhs.data(), rows, rhs.data(), inner, product_sgemm.data(), rows, ws);
    times.sgemm.push_back(seconds_since(t0));
  }
  Eigen::MatrixXf product_bf16(rows, cols);
  for (int r = 0; r < (rl::bf16_gemm_available() ? 5 : 0); ++r) {
    auto t0 = Clock::now();
    rl::gemm_bf16(false, false, rows, cols, inner, lhs.data(), rows, rhs.data(), inner, product_bf16.data(), rows, ws);
    times.bf16.push_back(seconds_since(t0));
  }
  const float check = product(0, 0);
  for (int r = 0; r < 3; ++r) {
    auto t0 = Clock::now();
    naive_gemm(lhs, rhs, product);
    times.naive.push_back(seconds_since(t0));
  }
  times.naive_matches = std::abs(product(0, 0) - check) < 1e-3f * (1 + std::abs(check));
  return times;
}

// Baselines on the dominant shape, a hidden layer GEMM of one minibatch (512 x 512 x 256), beside
// the core's measured peaks and what they leave as the least time of an iteration.
void time_gemm_baselines(const PpoBench& bench) {
  const int rows = bench.options.hidden, inner = bench.options.hidden, cols = bench.cfg.batch_size;
  const double gemm_flops = 2.0 * rows * inner * cols;
  const double gflop = bench.flops * 1e-9;
  const GemmTimes times = time_gemm_kernels(rows, inner, cols);
  const double eigen_rate = gemm_flops / median(times.eigen) * 1e-9;
  const double naive_rate = gemm_flops / median(times.naive) * 1e-9;
  const double peak = peak_fma_gflops();
  const double peak16 = peak_bf16_gflops();
  std::printf("\n  ceiling: measured fp32 FMA peak of this core %.1f GFLOP/s -> an iteration "
              "needs >= %.2f s in float32\n",
              peak, gflop / peak);
  if (peak16 > 0)
    std::printf("           measured bf16 dot-product peak %.1f GFLOP/s -> >= %.2f s with bf16 "
                "products\n",
                peak16, gflop / peak16);
  std::printf("\n  baseline, GEMM %d x %d x %d:\n", rows, inner, cols);
  std::printf("    Eigen          %.1f GFLOP/s (%.0f%% of peak; at this rate an iteration is "
              "%.2f s of pure GEMM)\n",
              eigen_rate, 100 * eigen_rate / peak, gflop / eigen_rate);
  if (!times.sgemm.empty()) {
    const double sgemm_rate = gemm_flops / median(times.sgemm) * 1e-9;
    std::printf("    rl::sgemm      %.1f GFLOP/s (%.0f%% of peak; used for the large layers) -> "
                "%.2fx Eigen\n",
                sgemm_rate, 100 * sgemm_rate / peak, sgemm_rate / eigen_rate);
  }
  if (!times.bf16.empty()) {
    const double bf16_rate = gemm_flops / median(times.bf16) * 1e-9;
    std::printf("    rl::gemm_bf16  %.1f GFLOP/s (%.0f%% of the bf16 peak) -> %.2fx Eigen\n", bf16_rate,
                100 * bf16_rate / peak16, bf16_rate / eigen_rate);
  }
  std::printf("    naive loops    %.1f GFLOP/s   -> Eigen is %.1fx faster%s\n", naive_rate, eigen_rate / naive_rate,
              times.naive_matches ? "" : " (MISMATCH!)");
}

void time_minibatch_precisions(const PpoBench& bench) {
  const int batch = bench.cfg.batch_size;
  const double f32 = minibatch_pass_seconds<float>(bench.options.hidden, batch, 5);
  const double f64 = minibatch_pass_seconds<double>(bench.options.hidden, batch, 5);
  std::printf("  baseline, one minibatch loss + gradient (both nets, batch %d):\n", batch);
  std::printf("    float32 %.2f ms, float64 %.2f ms  -> float32 is %.2fx faster\n", f32 * 1e3,
              f64 * 1e3, f64 / f32);
}

int run_bench(const BenchOptions& options) {
  Eigen::setNbThreads(1);
  if (options.precision == "bf16" && !rl::bf16_gemm_available()) {
    std::fprintf(stderr, "codesign: error: bench ppo: --precision bf16 needs AVX-512 BF16, which "
                         "this build/CPU does not have; allowed here: auto, float32\n");
    return 2;
  }
  const rl::MatmulPrecision precision =
      rl::resolve(value_of(rl::kMatmulChoiceNames, options.precision).value_or(rl::MatmulChoice::Auto));
  // The flops and the measured iteration come from time_main_iteration.
  PpoBench bench{options, bench_config(options), precision, std::min(options.reps, 3), 0.0, Measured{}};
  print_header(bench);
  time_main_iteration(bench);
  print_float32_baselines(bench);
  if (options.gru_hidden > 0) time_recurrent_iteration(bench);
  if (options.update_threads) time_update_threads(bench);
  if (options.with_kl) time_kl_limited_iteration(bench);
  time_gemm_baselines(bench);
  time_minibatch_precisions(bench);
  return 0;
}

}  // namespace

void add_bench_ppo_command(CLI::App& bench, Runner& run) {
  auto opts = std::make_shared<BenchOptions>();
  CLI::App* cmd = bench.add_subcommand(
      "ppo", "Wall time of one PPO iteration at the paper's sizes (one thread), GFLOP/s");
  cmd->add_option("--reps", opts->reps, "Timed repetitions (median reported)")
      ->check(CLI::Range(1, 100));
  cmd->add_option("--envs", opts->n_envs, "Parallel environments")->check(CLI::Range(1, 4096));
  cmd->add_option("--steps", opts->n_steps, "Steps per environment per rollout")
      ->check(CLI::Range(1, 100000));
  cmd->add_option("--hidden", opts->hidden, "Width of each of the three hidden layers")
      ->check(CLI::Range(1, 8192));
  cmd->add_flag("!--no-kl-run", opts->with_kl, "Skip the extra run with target_kl 0.02");
  cmd->add_flag("!--no-update-threads", opts->update_threads,
                "Skip the update on 2 threads (actor and critic side by side) against 1");
  cmd->add_option("--gru-hidden", opts->gru_hidden,
                  "Units of the recurrent policy's GRUs in its iteration beside the MLP's (0: skip it)")
      ->check(CLI::Range(0, 4096));
  cmd->add_option("--precision", opts->precision,
                  "Matrix products: auto (bf16 where available), float32 or bf16")
      ->check(CLI::IsMember({"auto", "float32", "bf16"}));
  cmd->callback([opts, &run] { run = [opts] { return run_bench(*opts); }; });
}

}  // namespace codesign::app
