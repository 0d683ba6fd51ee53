#pragma once
// The simulator's state and its internal operations (Simulator::Impl), shared by the files that
// implement them; not part of the fem library's interface (only src/fem/simulator*.cpp include it).
//   simulator.cpp             the public wrapper, reset, the time step (advance) and settle()
//   simulator_forces.cpp      the force pass and the products with K(x) and A
//   simulator_reference.cpp   the stored factors: assembly, node rotations, warps, contact columns
//   simulator_exact_step.cpp  the exact step: refactorisation and the contact LCP
//   simulator_fast_step.cpp   the fast step: preconditioned CG with an active contact set
//   simulator_snapshot.cpp    snapshots of the state and restore()
//   simulator_sensors.cpp     the sensors and the readings derived from the state
#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "fem/cholmod_factor.hpp"
#include "fem/corotated_batch.hpp"
#include "fem/scene.hpp"
#include "fem/simulator.hpp"
#include "fem/system_matrix.hpp"

namespace codesign::fem {

struct Simulator::Impl {
  // A stored factorisation of A_ref (world frame) used by the fast method, with the per-node
  // rotations at the time it was assembled.
  struct Reference {
    CholmodFactor factor;
    std::vector<Eigen::Matrix3d> node_rot;  // per free node
    double dt = 0.0;
    // A_ref⁻¹ e_d for unit loads along x, y, z at contact candidates (free-DOF vectors), computed
    // on first use and kept until the next factorisation (empty: not computed yet).
    std::vector<std::array<Eigen::VectorXd, 3>> cols;
    bool valid = false;
  };

  std::shared_ptr<const Model> model;
  SceneConfig scene;
  SolverConfig solver;
  int n = 0;
  std::vector<int> free_index, free_nodes;
  int nfree = 0;
  double mu = 0.0, lambda = 0.0;

  // State.
  Eigen::VectorXd x, v, f;
  Eigen::VectorXd v_prev;    // velocity of the step before (fast: CG start v + (v − v_prev))
  double omega_last = 0.0;   // base angular velocity of the last step [rad/s]
  // The element loops (force pass, K·u), vectorised across elements. It holds the element
  // rotations (polar rotation at x per tet, and the same as a quaternion warm start), written
  // by each force pass: the simulator's one store of them.
  CorotatedBatch batch;
  std::vector<Eigen::Matrix3d> fibre_kt;  // per fibre spring: tangent at x (last force pass)
  double t = 0.0;
  double theta = 0.0, theta_from = 0.0, theta_to = 0.0;
  int ramp_total = 0, ramp_done = 0;
  std::vector<double> pressures_Pa{0.0, 0.0};
  double z_touch = 0.0, z_mean = 0.0;
  std::vector<std::pair<int, double>> contacts;
  std::vector<char> was_active;  // per contact candidate
  bool broken = false;
  int factorisations = 0;

  // Exact machinery (also used to build references).
  std::optional<SystemMatrix> A;
  CholmodFactor exact_factor;
  bool exact_analysed = false;
  // Fast machinery.
  // Per step kind (0: dynamic dt, 1: static dt): rest = at the reset placement (built once, kept
  // across reset()), cur = refactorised later at a deformed state.
  struct RefSlot {
    Reference rest, cur;
    enum class Use { Rest, Cur, Settled } use = Use::Rest;
  } slots[2];
  // The dynamic factor built at the end of the last settle(), kept apart from `cur` (which later
  // refactorisations overwrite) so that restoring a snapshot of that settled state reuses it
  // instead of factorising the same matrix again. `settled_token` identifies it: a new token per
  // settle, shared with the snapshots taken while the factor was the one in use.
  Reference settled;
  std::shared_ptr<const int> settled_token;

  Reference& active(RefSlot& sl) {
    switch (sl.use) {
      case RefSlot::Use::Cur: return sl.cur;
      case RefSlot::Use::Settled: return settled;
      case RefSlot::Use::Rest: break;
    }
    return sl.rest;
  }
  RefSlot& slot(bool dynamic) { return slots[dynamic ? 0 : 1]; }
  Eigen::VectorXd work_u;                       // apply_ref_inverse's rotated right-hand side
  std::vector<Eigen::Matrix3d> node_rot, warp;  // per free node (fast method)
  std::vector<Eigen::Quaterniond> node_qrot;
  // update_node_rotations' per-element data in one contiguous array (the free index of each of
  // its nodes, -1 where fixed, and its rest volume), built on first use; and its accumulators.
  struct RotationTerm {
    std::array<int, 4> free;
    double volume;
  };
  std::vector<RotationTerm> rotation_terms;
  std::vector<Eigen::Vector4d> rotation_acc;

  // ------------------------------------------------ simulator.cpp: set-up and the time step
  Impl(std::shared_ptr<const Model> m, const SceneConfig& sc, const SolverConfig& so);
  void reset();
  Eigen::Matrix3d base_rotation(double th) const { return rotation_y(scene.alpha_rad() + th); }
  double plate_at(double time) const {
    return z_mean + scene.plate_amplitude_mm * std::sin(scene.omega() * time + scene.plate_phase_rad);
  }
  // Marks the simulator failed and returns status s with its reason.
  StepResult fail(StepStatus s, std::string why);
  // One step of dt (dynamic) or of static_dt with the velocity zeroed (static); the plate at
  // plate_override when given (settle()'s rising plate).
  StepResult advance(bool dynamic, std::optional<double> plate_override = std::nullopt);
  void coefficients(double dt, double& c_m, double& c_k) const {
    c_m = 1.0 + dt * model->material.rayleigh_mass_per_s;
    c_k = dt * model->material.rayleigh_stiffness_s + dt * dt;
  }
  // Gather / scatter between all-DOF and free-DOF vectors.
  void gather(const Eigen::VectorXd& all, Eigen::VectorXd& fr) const {
    fr.resize(3 * nfree);
    for (int k = 0; k < nfree; ++k) fr.segment<3>(3 * k) = all.segment<3>(3 * free_nodes[k]);
  }
  void scatter_add(const Eigen::VectorXd& fr, Eigen::VectorXd& all) const {
    for (int k = 0; k < nfree; ++k) all.segment<3>(3 * free_nodes[k]) += fr.segment<3>(3 * k);
  }

  // ------------------------------------------------ simulator_forces.cpp
  // Total force at x (elastic + fibres + gravity + pressure) into f; rotations updated.
  // Returns a failure status if an element is inverted or the state is not finite.
  // rotation_tolerance: accuracy of the polar rotations [rad] (1e-14 for the exact step; the
  // fast step uses 1e-6, a force error of the same relative size, far below its CG tolerance).
  // With u, also ku = K(x) u (fused into the element pass).
  StepStatus force_pass(const Eigen::VectorXd& xx, Eigen::VectorXd& ff, std::string& why,
                        const Eigen::VectorXd* u = nullptr, Eigen::VectorXd* ku = nullptr,
                        double rotation_tolerance = 1e-14);
  // y = K(x) u (co-rotated elastic + fibre tangents), all DOFs.
  void apply_K(const Eigen::VectorXd& u, Eigen::VectorXd& y);
  // Fibre tangents (cached by the last force pass) times u, added to y.
  void add_fibre_K(const Eigen::VectorXd& u, Eigen::VectorXd& y) const;
  // y = A u with A = c_m M + c_k K(x), all DOFs.
  void apply_A(const Eigen::VectorXd& u, double c_m, double c_k, Eigen::VectorXd& y);
  // Force scale of the "force" stopping rule [µN]: the larger of ‖f‖ (the step's total force
  // on the free DOFs: elastic + fibres + gravity + pressure, i.e. the contact reactions when the
  // body is near balance) and the norm of the body's weight on the free DOFs (so an unloaded body
  // at rest keeps a finite scale). Neither depends on the velocities.
  double force_scale() const;

  // ------------------------------------------------ simulator_reference.cpp: stored factors
  // Assembles A(x) and factorises it into exact_factor (false: not positive definite).
  bool build_exact(double dt);
  // The same into ref, with the node rotations of this state and its contact columns cleared.
  bool build_reference(Reference& ref, double dt);
  // Node rotations: normalised volume-weighted sum of the adjacent element rotations as unit
  // quaternions (sign-aligned with the node's previous rotation) — a cheap rotation average;
  // it only shapes the preconditioner.
  void update_node_rotations();
  // Q_k = R_k(now) R_k(ref)ᵀ: how far each node's frame turned since the reference.
  void update_warp(const Reference& ref);
  // Makes sure the reference columns of candidate c exist.
  bool ensure_columns(Reference& ref, int c);
  // y = Q A_ref⁻¹ Qᵀ r (free DOFs), Q = blockdiag(warp): the stored inverse turned node by node.
  void apply_ref_inverse(Reference& ref, const Eigen::VectorXd& r, Eigen::VectorXd& y);

  // ------------------------------------------------ simulator_exact_step.cpp
  // Exact: factorise A(x), free solve, then the contact LCP with exact Delassus columns.
  StepResult exact_solve(const Eigen::VectorXd& vg, const Eigen::VectorXd& b, double plate_new, double dt,
                         double c_m, double c_k, Eigen::VectorXd& vnew);

  // ------------------------------------------------ simulator_fast_step.cpp
  // Fast: constrained PCG (see simulator.hpp). Active contact nodes get their vertical velocity
  // prescribed so they land on the plate; the multiplier is the reaction at that DOF.
  // kvg = K(x) vg from the fused force pass (saves one mat-vec in the first round).
  StepResult fast_solve(const Eigen::VectorXd& vg, const Eigen::VectorXd& kvg, const Eigen::VectorXd& b,
                        double plate_new, double dt, double c_m, double c_k, Eigen::VectorXd& vnew);
};

}  // namespace codesign::fem
