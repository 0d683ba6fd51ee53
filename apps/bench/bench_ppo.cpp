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

// Median times of `reps` iterations (after one warm-up) of a fresh model with the given
// product precision / GEMM choice.
struct Measured {
  double wall = 0, cpu = 0, rollout = 0, update = 0;
};
Measured measure(const rl::PpoConfig& cfg, int n_envs, int reps, rl::MatmulPrecision precision,
                 bool fast_gemm) {
  rl::Rng rng(2024);
  rl::ActorCritic model(6, 1, cfg.actor_hidden, cfg.critic_hidden);
  model.init_orthogonal(rng);
  model.set_fast_gemm(fast_gemm);
  model.set_matmul_precision(precision);
  rl::Adam adam = rl::make_adam(cfg);
  run_iteration(model, adam, cfg, n_envs, rng);  // warm-up (allocations, page faults)
  std::vector<double> total, cpu, rollout, update;
  for (int r = 0; r < reps; ++r) {
    const IterationTimes t = run_iteration(model, adam, cfg, n_envs, rng);
    total.push_back(t.total());
    cpu.push_back(t.cpu);
    rollout.push_back(t.rollout);
    update.push_back(t.update);
  }
  return {median(total), median(cpu), median(rollout), median(update)};
}

int run_bench(const BenchOptions& o) {
  Eigen::setNbThreads(1);
  rl::PpoConfig cfg = rl::paper_ppo_config();
  cfg.n_steps = o.n_steps;
  cfg.actor_hidden = cfg.critic_hidden = {o.hidden, o.hidden, o.hidden};
  const int samples = o.n_envs * o.n_steps;
  if (o.precision == "bf16" && !rl::bf16_gemm_available()) {
    std::fprintf(stderr, "codesign: error: bench ppo: --precision bf16 needs AVX-512 BF16, which "
                         "this build/CPU does not have; allowed here: auto, float32\n");
    return 2;
  }
  const rl::MatmulPrecision precision =
      rl::resolve(value_of(rl::kMatmulChoiceNames, o.precision).value_or(rl::MatmulChoice::Auto));

  std::printf("PPO iteration benchmark (one thread, Eigen %d.%d.%d, SIMD: %s)\n",
              EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION,
              Eigen::SimdInstructionSetsInUse());
  std::printf("  %d envs x %d steps = %d samples, obs 6, act 1, actor/critic [%d, %d, %d], "
              "batch %d, %d epochs\n",
              o.n_envs, o.n_steps, samples, o.hidden, o.hidden, o.hidden, cfg.batch_size,
              cfg.n_epochs);
  std::printf("  matrix products: %s (--precision %s; training's default is auto)\n",
              describe(precision), o.precision.c_str());
  {
    rl::ActorCritic probe(6, 1, cfg.actor_hidden, cfg.critic_hidden);
    std::printf("  parameters: %lld (actor %lld, critic %lld, log_std %lld)\n",
                static_cast<long long>(probe.num_params()),
                static_cast<long long>(probe.actor().num_params()),
                static_cast<long long>(probe.critic().num_params()),
                static_cast<long long>(probe.log_std().size()));
  }

  // target_kl disabled: all epochs run.
  cfg.target_kl.reset();
  rl::ActorCritic counter(6, 1, cfg.actor_hidden, cfg.critic_hidden);
  const double flops = iteration_flops(counter, samples, cfg.n_epochs);
  const Measured main_run = measure(cfg, o.n_envs, o.reps, precision, true);
  const double med = main_run.wall;
  std::printf("\n  target_kl off (all %d epochs), median of %d:\n", cfg.n_epochs, o.reps);
  std::printf("    iteration      %.3f s   (rollout forwards %.3f s, update %.3f s)\n", med,
              main_run.rollout, main_run.update);
  std::printf("    thread CPU     %.3f s\n", main_run.cpu);
  std::printf("    GEMM work      %.1f GFLOP  ->  %.1f GFLOP/s (wall), %.1f GFLOP/s (CPU time)\n",
              flops * 1e-9, flops * 1e-9 / med, flops * 1e-9 / main_run.cpu);
  std::printf("    goal 0.8 s:    %s (needs %.0f GFLOP/s)\n", med <= 0.8 ? "met" : "NOT met",
              flops * 1e-9 / 0.8);

  const int base_reps = std::min(o.reps, 3);
  // One baseline: the same iteration in float32 with or without the own GEMM kernel.
  auto baseline = [&](bool fast_gemm, const char* what, const char* winner) {
    const Measured b = measure(cfg, o.n_envs, base_reps, rl::MatmulPrecision::Float32, fast_gemm);
    std::printf("\n  baseline, same iteration with %s, median of %d:\n", what, base_reps);
    std::printf("    iteration      %.3f s wall, %.3f s CPU -> %.1f GFLOP/s (CPU time)\n", b.wall,
                b.cpu, flops * 1e-9 / b.cpu);
    std::printf("    %s %.2fx faster (CPU time; %.2fx wall)\n", winner, b.cpu / main_run.cpu,
                b.wall / med);
  };
  if (precision == rl::MatmulPrecision::BFloat16)
    baseline(true, "float32 products (rl::sgemm)", "bf16 products are");
  baseline(false, "Eigen's float32 GEMM only", "the measured configuration is");

  if (o.gru_hidden > 0) {
    // The recurrent policy at the same sizes, target_kl off: the GRUs' products are small
    // (gru_hidden x 6 and gru_hidden x gru_hidden per step), so they run in float32 with Eigen;
    // the MLP heads use `precision` as above.
    rl::Rng rng(2024);
    rl::RecurrentActorCritic gru(6, 1, o.gru_hidden, cfg.actor_hidden, cfg.critic_hidden);
    gru.init(rng);
    gru.set_matmul_precision(precision);
    rl::Adam adam = rl::make_adam(cfg);
    run_recurrent_iteration(gru, adam, cfg, o.n_envs, rng);  // warm-up
    std::vector<double> total, cpu, rollout, update;
    for (int r = 0; r < base_reps; ++r) {
      const IterationTimes t = run_recurrent_iteration(gru, adam, cfg, o.n_envs, rng);
      total.push_back(t.total());
      cpu.push_back(t.cpu);
      rollout.push_back(t.rollout);
      update.push_back(t.update);
    }
    std::printf("\n  recurrent policy (ppo.policy = \"gru\", GRU %d before each MLP; %d envs per minibatch), "
                "target_kl off, median of %d:\n",
                o.gru_hidden, rl::sequences_per_minibatch(cfg, o.n_envs), base_reps);
    std::printf("    iteration      %.3f s wall, %.3f s CPU (rollout forwards %.3f s, update %.3f s)\n",
                median(total), median(cpu), median(rollout), median(update));
    std::printf("    vs the MLP     %.2fx its CPU time; parameters %lld (GRUs %lld)\n", median(cpu) / main_run.cpu,
                static_cast<long long>(gru.num_params()),
                static_cast<long long>(gru.actor_gru().num_params() + gru.critic_gru().num_params()));
  }

  if (o.update_threads) {
    // The update with the actor's and the critic's passes side by side on two threads (as a
    // co-design run does on its rollout threads), against one thread, from the same state and
    // seeds: wall times (a thread's CPU time no longer covers the work) and whether the trained
    // parameters are the same to the bit.
    auto pair_run = [&](auto make_model, auto iterate, const char* what) {
      auto one = make_model(), two = make_model();
      rl::Adam adam_1 = rl::make_adam(cfg), adam_2 = rl::make_adam(cfg);
      rl::ThreadPool pool(2);
      rl::Rng w1(99), w2(99);
      iterate(one, adam_1, w1, nullptr);  // warm-up
      iterate(two, adam_2, w2, &pool);
      std::vector<double> u1, u2;
      for (int r = 0; r < base_reps; ++r) {
        rl::Rng r1(100 + r), r2(100 + r);
        u1.push_back(iterate(one, adam_1, r1, nullptr).update);
        u2.push_back(iterate(two, adam_2, r2, &pool).update);
      }
      const bool same = one.actor().params() == two.actor().params() && one.critic().params() == two.critic().params();
      std::printf("\n  %s: update with actor and critic side by side on 2 threads, median of %d (wall):\n", what,
                  base_reps);
      std::printf("    update         %.3f s on 2 threads vs %.3f s on 1 -> %.2fx faster; parameters after %d "
                  "iterations %s\n",
                  median(u2), median(u1), median(u1) / median(u2), base_reps + 1,
                  same ? "identical to the bit" : "DIFFER (a bug)");
    };
    pair_run(
        [&] {
          rl::Rng init(2024);
          rl::ActorCritic m(6, 1, cfg.actor_hidden, cfg.critic_hidden);
          m.init_orthogonal(init);
          m.set_matmul_precision(precision);
          return m;
        },
        [&](rl::ActorCritic& m, rl::Adam& a, rl::Rng& r, rl::ThreadPool* p) {
          return run_iteration(m, a, cfg, o.n_envs, r, p);
        },
        "MLP");
    if (o.gru_hidden > 0)
      pair_run(
          [&] {
            rl::Rng init(2024);
            rl::RecurrentActorCritic m(6, 1, o.gru_hidden, cfg.actor_hidden, cfg.critic_hidden);
            m.init(init);
            m.set_matmul_precision(precision);
            return m;
          },
          [&](rl::RecurrentActorCritic& m, rl::Adam& a, rl::Rng& r, rl::ThreadPool* p) {
            return run_recurrent_iteration(m, a, cfg, o.n_envs, r, p);
          },
          "GRU");
  }

  if (o.with_kl) {
    cfg.target_kl = 0.02;
    rl::Rng rng_kl(7);
    rl::ActorCritic fresh(6, 1, cfg.actor_hidden, cfg.critic_hidden);
    fresh.init_orthogonal(rng_kl);
    fresh.set_matmul_precision(precision);
    rl::Adam adam_kl = rl::make_adam(cfg);
    const IterationTimes t = run_iteration(fresh, adam_kl, cfg, o.n_envs, rng_kl);
    std::printf("\n  target_kl 0.02 (fresh policy, synthetic rewards), one run:\n");
    std::printf("    iteration      %.3f s   (%d epochs started, %d minibatches applied%s)\n",
                t.total(), t.stats.epochs_done, t.stats.minibatches_applied,
                t.stats.early_stopped ? ", KL early stop" : "");
  }

  // Baselines on the dominant shape: a hidden layer GEMM of one minibatch (512 x 512 x 256).
  const int m = o.hidden, k = o.hidden, n = cfg.batch_size;
  Eigen::MatrixXf a = Eigen::MatrixXf::Random(m, k), b = Eigen::MatrixXf::Random(k, n);
  Eigen::MatrixXf c(m, n);
  const double gemm_flops = 2.0 * m * k * n;
  std::vector<double> te, tn, tf;
  for (int r = 0; r < 5; ++r) {
    auto t0 = Clock::now();
    c.noalias() = a * b;
    te.push_back(seconds_since(t0));
  }
  rl::GemmWorkspace ws;
  Eigen::MatrixXf cf(m, n);
  for (int r = 0; r < (rl::fast_gemm_available() ? 5 : 0); ++r) {
    auto t0 = Clock::now();
    rl::sgemm(false, false, m, n, k, a.data(), m, b.data(), k, cf.data(), m, ws);
    tf.push_back(seconds_since(t0));
  }
  std::vector<double> tb16;
  Eigen::MatrixXf cb(m, n);
  for (int r = 0; r < (rl::bf16_gemm_available() ? 5 : 0); ++r) {
    auto t0 = Clock::now();
    rl::gemm_bf16(false, false, m, n, k, a.data(), m, b.data(), k, cb.data(), m, ws);
    tb16.push_back(seconds_since(t0));
  }
  const float check = c(0, 0);
  for (int r = 0; r < 3; ++r) {
    auto t0 = Clock::now();
    naive_gemm(a, b, c);
    tn.push_back(seconds_since(t0));
  }
  const double ge = gemm_flops / median(te) * 1e-9, gn = gemm_flops / median(tn) * 1e-9;
  const double peak = peak_fma_gflops();
  const double peak16 = peak_bf16_gflops();
  std::printf("\n  ceiling: measured fp32 FMA peak of this core %.1f GFLOP/s -> an iteration "
              "needs >= %.2f s in float32\n",
              peak, flops * 1e-9 / peak);
  if (peak16 > 0)
    std::printf("           measured bf16 dot-product peak %.1f GFLOP/s -> >= %.2f s with bf16 "
                "products\n",
                peak16, flops * 1e-9 / peak16);
  std::printf("\n  baseline, GEMM %d x %d x %d:\n", m, k, n);
  std::printf("    Eigen          %.1f GFLOP/s (%.0f%% of peak; at this rate an iteration is "
              "%.2f s of pure GEMM)\n",
              ge, 100 * ge / peak, flops * 1e-9 / ge);
  if (!tf.empty()) {
    const double gf = gemm_flops / median(tf) * 1e-9;
    std::printf("    rl::sgemm      %.1f GFLOP/s (%.0f%% of peak; used for the large layers) -> "
                "%.2fx Eigen\n",
                gf, 100 * gf / peak, gf / ge);
  }
  if (!tb16.empty()) {
    const double gb = gemm_flops / median(tb16) * 1e-9;
    std::printf("    rl::gemm_bf16  %.1f GFLOP/s (%.0f%% of the bf16 peak) -> %.2fx Eigen\n", gb,
                100 * gb / peak16, gb / ge);
  }
  std::printf("    naive loops    %.1f GFLOP/s   -> Eigen is %.1fx faster%s\n", gn, ge / gn,
              std::abs(c(0, 0) - check) < 1e-3f * (1 + std::abs(check)) ? "" : " (MISMATCH!)");

  const double f32 = minibatch_pass_seconds<float>(o.hidden, cfg.batch_size, 5);
  const double f64 = minibatch_pass_seconds<double>(o.hidden, cfg.batch_size, 5);
  std::printf("  baseline, one minibatch loss + gradient (both nets, batch %d):\n",
              cfg.batch_size);
  std::printf("    float32 %.2f ms, float64 %.2f ms  -> float32 is %.2fx faster\n", f32 * 1e3,
              f64 * 1e3, f64 / f32);
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
