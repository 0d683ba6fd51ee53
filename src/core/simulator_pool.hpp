#pragma once
// Simulators for the 110 designs, built lazily and shared by the environments of a run.
//
// Meshing a design (gmsh) and building its Model happens once per design; a Simulator (the
// Model plus its stored factorisations) is leased to one environment for as many episodes as
// that environment keeps the design, then returned for another environment to reuse.
// Simulator::reset() leaves no trace of earlier episodes (tests/core/whisker_env_test.cpp
// checks bit-identical episodes on a fresh and on a reused simulator), so which simulator
// object an episode gets never changes its result: leasing only saves construction time.
//
// Memory is bounded by what the run uses now, not by its history (docs/memory.md):
//  * a returned simulator gives up the factorisations it stored at deformed states
//    (fem::Simulator::drop_stored_factors; the next user rebuilds them as a new simulator
//    would), keeping the ones at the reset placement that every episode of the design reuses;
//  * the pool keeps at most as many idle (returned, not leased) simulators as the most it has had
//    leased at once — for a run, its number of environments ψ: a return over that bound destroys
//    the idle simulator returned longest ago, whatever its design;
//  * a design's model is dropped once no simulator of it is left and no simulator of it has been
//    asked for in the last model_keep_window() requests (4 × the design count: while the
//    distribution explores, a design is asked for about once in every design-count requests);
//    asked for again, it is meshed again, to the same bits (meshing is deterministic).
//
// Thread-safe: acquire()/release() may be called from the rollout threads concurrently.
#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "fem/simulator.hpp"
#include "fem/whisker_model.hpp"

namespace codesign::core {

class SimulatorPool {
 public:
  SimulatorPool(fem::WhiskerModelSpec spec, fem::SceneConfig scene, fem::SolverConfig solver);

  // The design's model (meshed on first use, unless a mesh was adopted). Throws what
  // build_whisker_model throws.
  std::shared_ptr<const fem::Model> model(int design);
  // Builds the design's model from a mesh made elsewhere (another process's pool, meshing with the
  // same spec: fem::whisker_model_from_mesh gives the model meshing here would, bit for bit), so
  // that model() need not mesh it: nearly all of a model's cost is meshing. Nothing happens if the
  // pool has the model already; returns whether it built it. Throws std::out_of_range for a bad
  // index and what whisker_model_from_mesh throws.
  bool adopt_mesh(int design, fem::TetMesh mesh);
  // The model of the design cast with its wall thicker by `wall_offset_mm` (negative: thinner;
  // 0: model(design)), meshed here on first use and kept for the pool's life: [randomize] wall_mm
  // asks for two such levels per design at most. Throws what build_whisker_model throws.
  std::shared_ptr<const fem::Model> cast_model(int design, double wall_offset_mm);
  bool has_model(int design) const;
  // The designs this pool has meshed itself (not adopted) since the last call, in that order.
  std::vector<int> take_meshed();
  // A simulator of the design, in an arbitrary earlier state: call reset() before use.
  std::unique_ptr<fem::Simulator> acquire(int design);
  // Gives a simulator of `design` back for reuse (nullptr is ignored), without the factors it
  // stored at deformed states; destroys the idle simulator returned longest ago if the idle ones then exceed
  // idle_limit().
  void release(int design, std::unique_ptr<fem::Simulator> sim);

  // The bound on idle simulators: the most simulators leased at once so far (at least 1).
  std::size_t idle_limit() const;
  // Simulators returned and kept for reuse, and simulators leased now.
  std::size_t idle() const;
  std::size_t leased() const;
  // Designs whose model the pool holds now.
  std::size_t models_held() const;
  // A model without simulators is dropped after model_keep_window() requests for simulators (of
  // any design) without one for it: kModelKeepRounds times the larger of the design count and
  // the idle bound.
  static constexpr std::uint64_t kModelKeepRounds = 4;
  std::uint64_t model_keep_window() const;

  const fem::SceneConfig& scene() const { return scene_; }
  const fem::SolverConfig& solver() const { return solver_; }
  const fem::WhiskerModelSpec& spec() const { return spec_; }
  // What the pool has built so far, read at once: simulators constructed and designs' models
  // built (one per design at most), with the thread CPU seconds they took (meshing included). Work
  // of the rollouts outside their settles and FEM steps (the benches' accounting), and what a rank
  // must spend before it can step a design new to it (cluster::BuildCosts).
  struct BuildStats {
    int simulators = 0, models = 0, adopted = 0;  // models: meshed here; adopted: from a given mesh
    int dropped = 0;                              // models dropped unused (counted again if rebuilt)
    double seconds = 0.0;        // all builds
    double model_seconds = 0.0;  // of which the meshed models
    double adopt_seconds = 0.0;  // and the adopted ones; the rest went into the simulators
    double seconds_per_model() const { return models > 0 ? model_seconds / models : 0.0; }
    double seconds_per_adopted() const { return adopted > 0 ? adopt_seconds / adopted : 0.0; }
    double seconds_per_simulator() const;
  };
  BuildStats build_stats() const;
  int constructed() const { return build_stats().simulators; }
  double build_seconds() const { return build_stats().seconds; }

 private:
  // Keeps a built model and counts its seconds (as adopted from a mesh, or meshed here).
  void store(int design, std::shared_ptr<const fem::Model> m, double seconds, bool adopted);

  const fem::WhiskerModelSpec spec_;
  const fem::SceneConfig scene_;
  const fem::SolverConfig solver_;
  mutable std::mutex mutex_;
  std::vector<std::shared_ptr<const fem::Model>> models_;              // per design
  // Returned simulators, the one returned longest ago first.
  struct Idle {
    int design;
    std::unique_ptr<fem::Simulator> sim;
  };
  std::deque<Idle> idle_;
  std::size_t leased_ = 0, peak_leased_ = 0;
  std::vector<int> live_;                  // per design: its simulators, leased or idle
  std::vector<std::uint64_t> last_used_;   // per design: acquisitions_ when last asked for or built
  std::uint64_t acquisitions_ = 0;         // simulators asked for so far
  std::size_t idle_limit_locked() const;
  std::uint64_t model_keep_window_locked() const;
  std::vector<std::unique_ptr<std::mutex>> build_mutex_;               // per design
  BuildStats built_;
  std::vector<int> meshed_;  // meshed here since the last take_meshed()
  // cast_model's models by (design, wall offset), built one at a time.
  std::map<std::pair<int, double>, std::shared_ptr<const fem::Model>> cast_;
  std::mutex cast_build_mutex_;
};

}  // namespace codesign::core
