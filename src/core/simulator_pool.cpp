#include "core/simulator_pool.hpp"

#include <algorithm>
#include <iterator>
#include <stdexcept>
#include <string>
#include <utility>

#include "base/thread_cpu_seconds.hpp"
#include "fem/design.hpp"

namespace codesign::core {

SimulatorPool::SimulatorPool(fem::WhiskerModelSpec spec, fem::SceneConfig scene, fem::SolverConfig solver)
    : spec_(std::move(spec)), scene_(scene), solver_(solver) {
  models_.resize(fem::kDesignCount);
  live_.assign(fem::kDesignCount, 0);
  last_used_.assign(fem::kDesignCount, 0);
  for (int j = 0; j < fem::kDesignCount; ++j) build_mutex_.push_back(std::make_unique<std::mutex>());
}

namespace {

void check_design(int design) {
  if (design < 0 || design >= fem::kDesignCount)
    throw std::out_of_range("SimulatorPool: design index " + std::to_string(design) + " outside 0..109");
}

}  // namespace

std::shared_ptr<const fem::Model> SimulatorPool::model(int design) {
  check_design(design);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (models_[design]) return models_[design];
  }
  // One builder per design; other designs may build at the same time (gmsh itself serialises).
  std::lock_guard<std::mutex> build(*build_mutex_[design]);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (models_[design]) return models_[design];
  }
  const double t0 = thread_cpu_seconds();
  std::shared_ptr<const fem::Model> m = fem::build_whisker_model(design, spec_);
  store(design, m, thread_cpu_seconds() - t0, false);
  return m;
}

std::shared_ptr<const fem::Model> SimulatorPool::cast_model(int design, double wall_offset_mm) {
  if (wall_offset_mm == 0.0) return model(design);
  check_design(design);
  const std::pair<int, double> key{design, wall_offset_mm};
  std::lock_guard<std::mutex> build(cast_build_mutex_);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (const auto it = cast_.find(key); it != cast_.end()) return it->second;
  }
  fem::Design d = fem::design_from_index(design);
  d.wall_mm += wall_offset_mm;
  const double t0 = thread_cpu_seconds();
  std::shared_ptr<const fem::Model> m = fem::build_whisker_model(d, spec_);
  std::lock_guard<std::mutex> lock(mutex_);
  built_.seconds += thread_cpu_seconds() - t0;
  return cast_[key] = std::move(m);
}

void SimulatorPool::store(int design, std::shared_ptr<const fem::Model> m, double seconds, bool adopted) {
  std::lock_guard<std::mutex> lock(mutex_);
  models_[design] = std::move(m);
  last_used_[design] = acquisitions_;  // a model built for use now is not one to drop
  built_.seconds += seconds;
  if (adopted) {
    built_.adopt_seconds += seconds;
    ++built_.adopted;
  } else {
    built_.model_seconds += seconds;
    ++built_.models;
    meshed_.push_back(design);
  }
}

bool SimulatorPool::adopt_mesh(int design, fem::TetMesh mesh) {
  check_design(design);
  std::lock_guard<std::mutex> build(*build_mutex_[design]);
  if (has_model(design)) return false;
  const double t0 = thread_cpu_seconds();
  std::shared_ptr<const fem::Model> m = fem::whisker_model_from_mesh(design, std::move(mesh), spec_);
  store(design, std::move(m), thread_cpu_seconds() - t0, true);
  return true;
}

bool SimulatorPool::has_model(int design) const {
  if (design < 0 || design >= fem::kDesignCount) return false;
  std::lock_guard<std::mutex> lock(mutex_);
  return models_[design] != nullptr;
}

std::vector<int> SimulatorPool::take_meshed() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<int> out;
  out.swap(meshed_);
  return out;
}

std::unique_ptr<fem::Simulator> SimulatorPool::acquire(int design) {
  std::shared_ptr<const fem::Model> m = model(design);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    peak_leased_ = std::max(peak_leased_, ++leased_);
    last_used_[design] = ++acquisitions_;
    // The most recently returned simulator of the design: the one least likely to be evicted next.
    for (auto it = idle_.rbegin(); it != idle_.rend(); ++it) {
      if (it->design != design) continue;
      std::unique_ptr<fem::Simulator> s = std::move(it->sim);
      idle_.erase(std::next(it).base());
      return s;
    }
    ++built_.simulators;
    ++live_[design];
  }
  const double t0 = thread_cpu_seconds();
  std::unique_ptr<fem::Simulator> sim;
  try {
    sim = std::make_unique<fem::Simulator>(std::move(m), scene_, solver_);
  } catch (...) {
    std::lock_guard<std::mutex> lock(mutex_);
    --leased_;
    --live_[design];
    throw;
  }
  const double spent = thread_cpu_seconds() - t0;
  std::lock_guard<std::mutex> lock(mutex_);
  built_.seconds += spent;
  return sim;
}

void SimulatorPool::release(int design, std::unique_ptr<fem::Simulator> sim) {
  if (!sim) return;
  // The factors it stored at deformed states would be rebuilt by the next user anyway (reset()
  // leaves no trace), and they are most of its memory.
  sim->drop_stored_factors();
  {
    std::unique_ptr<fem::Simulator> evicted;  // both destroyed outside the lock
    std::vector<std::shared_ptr<const fem::Model>> dropped;
    std::lock_guard<std::mutex> lock(mutex_);
    if (leased_ > 0) --leased_;
    idle_.push_back(Idle{design, std::move(sim)});
    if (idle_.size() > idle_limit_locked()) {
      --live_[idle_.front().design];
      evicted = std::move(idle_.front().sim);
      idle_.pop_front();
    }
    // Models of designs without a simulator that no one has asked for in a while.
    const std::uint64_t window = model_keep_window_locked();
    for (int d = 0; d < fem::kDesignCount; ++d) {
      if (!models_[d] || live_[d] > 0 || acquisitions_ - last_used_[d] <= window) continue;
      dropped.push_back(std::move(models_[d]));
      models_[d] = nullptr;
      ++built_.dropped;
    }
  }
}

std::uint64_t SimulatorPool::model_keep_window_locked() const {
  // A design drawn uniformly from D designs is asked for once in D requests on average, so a
  // window of a few times D (and of the idle bound, were it larger) keeps the models of a
  // distribution that still explores; (1 - 1/D)^(4D) < 2 % of them go between two draws.
  return kModelKeepRounds * std::max<std::uint64_t>(idle_limit_locked(), fem::kDesignCount);
}

std::size_t SimulatorPool::idle_limit_locked() const { return std::max<std::size_t>(peak_leased_, 1); }

std::uint64_t SimulatorPool::model_keep_window() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return model_keep_window_locked();
}

std::size_t SimulatorPool::models_held() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return static_cast<std::size_t>(std::count_if(models_.begin(), models_.end(), [](const auto& m) { return m != nullptr; }));
}

std::size_t SimulatorPool::idle_limit() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return idle_limit_locked();
}

std::size_t SimulatorPool::idle() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return idle_.size();
}

std::size_t SimulatorPool::leased() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return leased_;
}

double SimulatorPool::BuildStats::seconds_per_simulator() const {
  return simulators > 0 ? std::max(0.0, seconds - model_seconds - adopt_seconds) / simulators : 0.0;
}

SimulatorPool::BuildStats SimulatorPool::build_stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return built_;
}

}  // namespace codesign::core
