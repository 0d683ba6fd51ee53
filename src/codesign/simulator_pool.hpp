#pragma once
// Simulators for the 110 designs, built lazily and shared by the environments of a run.
//
// Meshing a design (gmsh) and building its Model happens once per design; a Simulator (the
// Model plus its stored factorisations) is leased to one environment for as many episodes as
// that environment keeps the design, then returned for another environment to reuse.
// Simulator::reset() leaves no trace of earlier episodes (tests/codesign/whisker_env_test.cpp
// checks bit-identical episodes on a fresh and on a reused simulator), so which simulator
// object an episode gets never changes its result: leasing only saves construction time.
//
// Thread-safe: acquire()/release() may be called from the rollout threads concurrently.
#include <memory>
#include <mutex>
#include <vector>

#include "fem/simulator.hpp"
#include "fem/whisker_model.hpp"

namespace codesign::core {

class SimulatorPool {
 public:
  SimulatorPool(fem::WhiskerModelSpec spec, fem::SceneConfig scene, fem::SolverConfig solver);

  // The design's model (meshed on first use). Throws what build_whisker_model throws.
  std::shared_ptr<const fem::Model> model(int design);
  // A simulator of the design, in an arbitrary earlier state: call reset() before use.
  std::unique_ptr<fem::Simulator> acquire(int design);
  // Gives a simulator of `design` back for reuse (nullptr is ignored).
  void release(int design, std::unique_ptr<fem::Simulator> sim);

  const fem::SceneConfig& scene() const { return scene_; }
  const fem::SolverConfig& solver() const { return solver_; }
  const fem::WhiskerModelSpec& spec() const { return spec_; }
  // Simulators constructed so far, and the thread CPU seconds spent building them and the designs'
  // models (meshing included): work of the rollouts outside their settles and FEM steps (for the
  // benches' accounting).
  int constructed() const;
  double build_seconds() const;
  // Of those: the designs' models built so far (one per design at most) and the thread CPU
  // seconds they took; the rest of build_seconds() went into the constructed simulators. What a
  // rank must spend before it can step a design new to it (cluster::BuildCosts).
  int models_built() const;
  double model_seconds() const;

 private:
  const fem::WhiskerModelSpec spec_;
  const fem::SceneConfig scene_;
  const fem::SolverConfig solver_;
  mutable std::mutex mutex_;
  std::vector<std::shared_ptr<const fem::Model>> models_;              // per design
  std::vector<std::vector<std::unique_ptr<fem::Simulator>>> free_;     // per design
  std::vector<std::unique_ptr<std::mutex>> build_mutex_;               // per design
  int constructed_ = 0, models_built_ = 0;
  double build_s_ = 0.0, model_s_ = 0.0;
};

}  // namespace codesign::core
