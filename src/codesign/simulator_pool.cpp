#include "codesign/simulator_pool.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

#include "base/thread_cpu_seconds.hpp"
#include "fem/design.hpp"

namespace codesign::core {

SimulatorPool::SimulatorPool(fem::WhiskerModelSpec spec, fem::SceneConfig scene, fem::SolverConfig solver)
    : spec_(std::move(spec)), scene_(scene), solver_(solver) {
  models_.resize(fem::kDesignCount);
  free_.resize(fem::kDesignCount);
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

void SimulatorPool::store(int design, std::shared_ptr<const fem::Model> m, double seconds, bool adopted) {
  std::lock_guard<std::mutex> lock(mutex_);
  models_[design] = std::move(m);
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
    auto& list = free_[design];
    if (!list.empty()) {
      std::unique_ptr<fem::Simulator> s = std::move(list.back());
      list.pop_back();
      return s;
    }
    ++built_.simulators;
  }
  const double t0 = thread_cpu_seconds();
  auto sim = std::make_unique<fem::Simulator>(std::move(m), scene_, solver_);
  const double spent = thread_cpu_seconds() - t0;
  std::lock_guard<std::mutex> lock(mutex_);
  built_.seconds += spent;
  return sim;
}

void SimulatorPool::release(int design, std::unique_ptr<fem::Simulator> sim) {
  if (!sim) return;
  std::lock_guard<std::mutex> lock(mutex_);
  free_[design].push_back(std::move(sim));
}

double SimulatorPool::BuildStats::seconds_per_simulator() const {
  return simulators > 0 ? std::max(0.0, seconds - model_seconds - adopt_seconds) / simulators : 0.0;
}

SimulatorPool::BuildStats SimulatorPool::build_stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return built_;
}

}  // namespace codesign::core
