#pragma once
// A run's LCM telemetry (docs/telemetry.md): after every iteration the rows of the CSV logs as
// messages; during training the state of environment 0 after every telemetry_train_every-th
// decision on its own channel and, with the recurrent policy, its memory after every decision;
// the traces of the final evaluation. Both training streams are stamped with the run's timestep at
// the start of the iteration they belong to. What publishing costs (messages, and the wall time of
// filling, encoding and sending them summed over threads) is counted for RunResult, whose figures
// `codesign bench telemetry` reports.
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include "core/evaluation.hpp"
#include "core/outer_loop.hpp"
#include "io/telemetry/telemetry.hpp"
#include "run/distribution_summary.hpp"

namespace codesign::run {

class RunTelemetry {
 public:
  // url "" = off: every call below then does nothing. train_every 0: no training steps published.
  RunTelemetry(const std::string& url, int train_every);
  RunTelemetry(const RunTelemetry&) = delete;  // the loop's observers hold this object
  RunTelemetry& operator=(const RunTelemetry&) = delete;

  bool enabled() const { return telemetry_->enabled(); }

  // Installs the training observers on the loop; this object must outlive its training.
  void observe_training(core::OuterLoop& loop);
  // The timestep the training streams are stamped with until the next call.
  void start_iteration(std::int64_t t) { iteration_start_t_.store(t, std::memory_order_relaxed); }

  void publish_iteration(const core::IterationReport& rep, const DistributionSummary& summary, double steps_per_s);
  // Every simulation step of the trace of an evaluated design, stamped with timestep t.
  void publish_trace(const core::DesignEvaluation& e, std::int64_t t);

  std::int64_t messages() const { return messages_.load(); }
  double seconds() const { return 1e-9 * static_cast<double>(ns_.load()); }

 private:
  // Counts `messages` and the wall time of its own lifetime.
  class Timed {
   public:
    Timed(RunTelemetry& owner, std::int64_t messages);
    ~Timed();
    Timed(const Timed&) = delete;
    Timed& operator=(const Timed&) = delete;

   private:
    RunTelemetry& owner_;
    std::int64_t start_ns_;
  };

  std::unique_ptr<io::Telemetry> telemetry_;
  int train_every_;
  std::atomic<std::int64_t> iteration_start_t_{0};
  std::atomic<std::int64_t> ns_{0}, messages_{0};
};

}  // namespace codesign::run
