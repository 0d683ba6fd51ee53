#pragma once
// Time stepping of the whisker scene: co-rotational FEM + gravity + cavity pressure + fibres,
// clamped base on a rotary stage, frictionless unilateral contact with a moving plate.
//
// One step (linearised implicit Euler, one linear solve, as SOFA's EulerImplicit):
//   (M + dt C + dt² K(x)) v⁺ = M v + dt f(x) + dt Jᵀλ,   x⁺ = x + dt v⁺,
// f = elastic + fibre + gravity + pressure (follower: from the current geometry), C = a M + b K.
// Base nodes are Dirichlet: their v⁺ brings them exactly onto R_y(α + θ⁺) X.
// Contact (Lagrange multipliers λ ≥ 0, one per plate-contact candidate node, vertical): with the
// free velocity v_f (λ = 0) and D = dt² J A⁻¹ Jᵀ, solve the LCP
//   g = z_f⁺ − z_plate⁺ + D λ ≥ 0,  λ ≥ 0,  gᵀλ = 0
// exactly by an active-set (principal pivoting) method; F = Σλ.
//
// Methods:
//  * Exact: assemble A = M + dt C + dt² K(x) on the free DOFs and refactorise it with CHOLMOD
//    every step; A⁻¹Jᵀ columns by extra solves.
//  * Fast: a stored CHOLMOD factor of A_ref (assembled at the reset placement, at the settled
//    state at the end of settle(), and again whenever a step needs more than
//    fast_refactor_iterations CG iterations), warped node by node — Q A_ref⁻¹ Qᵀ with
//    Q_k = R_k R_k,refᵀ, R_k the average rotation of the elements at node k (exact for a rigid
//    rotation: K = G K_ref Gᵀ) — preconditions a conjugate-gradient solve of the true
//    co-rotated system, applied matrix-free and warm-started from the previous velocity (plus
//    the rigid velocity change of the base).
//    Contact is handled inside the solve as an active set: active nodes get their vertical
//    velocity prescribed so they land on the plate (Dirichlet DOFs, projected out of the CG; the
//    preconditioner is the exact inverse of A_ref restricted to the free DOFs, via the stored
//    A_ref⁻¹ columns of the candidates), the multiplier is the reaction at that DOF,
//    λ = (A v − b)_z / dt; nodes with λ < 0 are released, penetrating ones added, and the CG
//    repeated until the set is stable — the same LCP as Exact, solved to the CG tolerance.
//    Equilibria do not depend on the tolerance; transients do, by O(fast_tolerance) (bench fem
//    prints the measured difference).
// Failures (non-finite state, inverted element, factorisation failure, LCP failure) are returned
// as a status; the simulator is then unusable until reset().
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "base/enum_names.hpp"
#include "base/range.hpp"
#include "fem/model.hpp"
#include "fem/scene.hpp"
#include "fem/sensors.hpp"

namespace codesign::fem {

enum class StepMethod { Exact, Fast };
inline constexpr EnumNames<StepMethod, 2> kStepMethodNames{{{StepMethod::Fast, "fast"}, {StepMethod::Exact, "exact"}}};

// When the fast step's CG stops (‖r‖ the residual of the step's equations on the free DOFs, tol
// = SolverConfig::fast_tolerance):
//  * Relative: ‖r‖ ≤ tol · max(‖M v + dt f‖, ‖r0‖), r0 the residual of the warm start. The
//    warm start's residual grows with the change of the base's angular velocity (at the
//    decision boundaries of `bench fem --turn-deg 5` it is far above ‖b‖), so fast turns
//    loosen the test.
//  * Force: ‖r‖ ≤ tol · dt · max(‖f‖, ‖w‖), f the step's total force and w the body's weight,
//    both on the free DOFs: a residual force relative to the load of the design, independent
//    of the velocities and of the warm start (docs/physics.md, "Benchmark and accuracy", its
//    paragraph "A stopping rule that does not loosen with the base's speed").
enum class FastStop { Relative, Force };
inline constexpr EnumNames<FastStop, 2> kFastStopNames{{{FastStop::Relative, "relative"}, {FastStop::Force, "force"}}};

struct SolverConfig {
  StepMethod method = StepMethod::Fast;
  double dt_s = 0.01;
  double static_dt_s = 1.0;           // pseudo time step of static_step()/settle()
  // Fast: PCG on the free DOFs (active contacts and base fixed), preconditioned by the stored
  // factor; stops by the rule fast_stop at fast_tolerance, or after fast_max_iterations.
  double fast_tolerance = 2e-3;
  FastStop fast_stop = FastStop::Relative;  // "relative" | "force" ([solver] fast_stop)
  int fast_max_iterations = 50;
  // Refactorise the stored factor at the current state when a step needed more than this many
  // PCG iterations in total.
  int fast_refactor_iterations = 4;
  // Fast: an inactive candidate more than this below the plate after the solve enters the
  // active set (Exact: 1e-9 mm).
  double contact_tolerance_mm = 1e-4;
  double contact_margin_mm = 1.0;     // candidates closer than this (after the free step) enter the LCP
};

enum class StepStatus { Ok, NonFinite, InvertedElement, SolverFailure, ContactFailure };
inline constexpr EnumNames<StepStatus, 5> kStepStatusNames{{{StepStatus::Ok, "ok"},
                                                            {StepStatus::NonFinite, "non_finite"},
                                                            {StepStatus::InvertedElement, "inverted_element"},
                                                            {StepStatus::SolverFailure, "solver_failure"},
                                                            {StepStatus::ContactFailure, "contact_failure"}}};
const char* to_string(StepStatus s);

struct StepResult {
  StepStatus status = StepStatus::Ok;
  std::string reason;                 // empty when ok
  int iterations = 0;                 // linear iterations (fast) or 1 (exact)
  bool refactorised = false;
  // Fast: ‖r‖ / dt at the end of the last CG, the out-of-balance force [µN] the step left on
  // the free DOFs (0 for the exact step).
  double residual_force_uN = 0.0;
  bool ok() const { return status == StepStatus::Ok; }
};

class Simulator {
 public:
  Simulator(std::shared_ptr<const Model> model, const SceneConfig& scene, const SolverConfig& solver);
  ~Simulator();
  Simulator(Simulator&&) noexcept;
  Simulator& operator=(Simulator&&) noexcept;

  // Undeformed placement at θ = 0, v = 0, t = 0, pressures 0, plate at z_touch (+ U sin(phase)
  // motion only starts with step()).
  void reset();
  // Frees the factorisations and solves the simulator has stored as it ran (the fast method's
  // references at deformed states, the settled factor, the exact step's factor), keeping what
  // construction built and the references at the reset placement, which every episode reuses.
  // They are rebuilt on demand exactly as a new simulator builds them, so results do not change;
  // for a simulator that waits unused (core::SimulatorPool's idle ones), whose stored factors are
  // most of its memory. Call reset() before using it again.
  void drop_stored_factors();
  // What a settle() is for. Episode: dynamic steps follow, so the fast method ends with a
  // factorisation of the dynamic system at the settled state (their preconditioner). Reading:
  // only the settled state is read (the strain sensor's zero), then the simulator is reset; the
  // states are the same bits as Episode's, without that factorisation (about a fifth of a
  // settle's cost), and step() afterwards would precondition from the reset placement's factor.
  enum class SettleFor { Episode, Reading };
  // Quasi-static loading: `settle_steps` static steps raising the plate from z_touch to z0
  // (with the current pressures and gravity) and 5 more at z0, then zero velocity. t stays 0.
  StepResult settle(SettleFor purpose = SettleFor::Episode);
  // One static step: the same linearised solve with dt = static_dt_s, time and plate frozen,
  // velocity zeroed afterwards (a damped Newton iteration towards equilibrium).
  StepResult static_step();
  // One dynamic step of dt: advances t, the plate and the base angle.
  StepResult step();

  // Cavity pressures [kPa] (chamber 0, chamber 1); values for missing chambers are ignored.
  void set_pressures_kPa(double p0, double p1);
  // θ moves linearly from its current value to `theta_rad` over the next n_substeps steps
  // (n_substeps ≥ 1), then stays.
  void set_base_angle_target(double theta_rad, int n_substeps);
  // Sets θ at once (used for static sweeps; the base nodes jump on the next step/static_step).
  void set_base_angle(double theta_rad);
  // Plate: override the mean height (world z) — default comes from the scene's preload.
  void set_plate_mean_z(double z0_mm);
  // Plate: phase of the oscillation, z_plate = z0 + U sin(ω t + phase). Kept across reset();
  // set it before settle(), which loads the body up to the plate height at t = 0.
  void set_plate_phase(double phase_rad);

  // A copy of the simulator's state: everything a later step reads (positions, velocities,
  // element rotations, contact set, time, base-angle ramp, plate, pressures). restore() puts it
  // back and, for the fast method, refactorises the stored preconditioner at the restored state
  // when the snapshot had one, so steps after restore() are bit-identical to the steps after
  // snapshot() (tests/fem/snapshot_test.cpp). Used to start a repeated episode from its settled
  // state without settling again. A snapshot only fits simulators of the same model.
  class Snapshot {
   public:
    Snapshot() = default;
    bool empty() const { return !data_; }

   private:
    friend class Simulator;
    struct Data;
    std::shared_ptr<const Data> data_;
  };
  Snapshot snapshot() const;
  // Throws std::invalid_argument for an empty snapshot or one of another model.
  StepResult restore(const Snapshot& snapshot);

  Sensors sensors() const;
  // Per tet: axial engineering strain ‖F x̂‖ − 1 at the current state (for plots / VTK).
  std::vector<double> element_axial_strain() const;
  double time() const;
  double theta() const;
  double plate_z() const;             // current plate height
  double plate_touch_z() const;       // z_touch (scene.hpp)
  const Eigen::VectorXd& positions() const;   // 3N world
  const Eigen::VectorXd& velocities() const;  // 3N world
  // Contact multipliers of the last step per contact node [µN] (node index, λ).
  const std::vector<std::pair<int, double>>& contact_forces() const;
  // Force the clamp exerts on the body [µN], world, from the static balance at the current
  // state: −Σ_{base nodes}(f_elastic + f_fibre + f_gravity + f_pressure). At rest:
  // base_reaction + contact (0,0,F) + gravity (0,0,−m g) + net pressure force = 0.
  Eigen::Vector3d base_reaction() const;
  // Net external pressure force on the body [µN] (zero for a closed cavity in any state).
  Eigen::Vector3d pressure_force() const;
  const Model& model() const;
  const SceneConfig& scene() const;
  const SolverConfig& solver() const;
  int factorisations() const;         // CHOLMOD numeric factorisations so far

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace codesign::fem
