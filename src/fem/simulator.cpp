#include "fem/simulator.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "fem/cholmod_factor.hpp"
#include "fem/contact.hpp"
#include "fem/corotated_batch.hpp"
#include "fem/pressure.hpp"
#include "fem/system_matrix.hpp"

namespace codesign::fem {

const char* to_string(StepStatus s) {
  switch (s) {
    case StepStatus::Ok: return "ok";
    case StepStatus::NonFinite: return "non_finite";
    case StepStatus::InvertedElement: return "inverted_element";
    case StepStatus::SolverFailure: return "solver_failure";
    case StepStatus::ContactFailure: return "contact_failure";
  }
  return "unknown";
}

namespace {

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

}  // namespace

struct Simulator::Impl {
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
  Eigen::VectorXd work_b, work_r, work_u, work_y;
  std::vector<Eigen::Matrix3d> node_rot, warp;  // per free node (fast method)
  std::vector<Eigen::Quaterniond> node_qrot;

  Impl(std::shared_ptr<const Model> m, const SceneConfig& sc, const SolverConfig& so)
      : model(std::move(m)), scene(sc), solver(so) {
    n = model->node_count();
    free_index.assign(n, -1);
    for (int i = 0; i < n; ++i)
      if (!model->is_base[i]) free_index[i] = nfree++, free_nodes.push_back(i);
    mu = model->material.lame_mu();
    lambda = model->material.lame_lambda();
    A.emplace(*model, free_index);
    batch = CorotatedBatch(model->mesh.tets, model->rest, mu, lambda);
    reset();
  }

  Eigen::Matrix3d base_rotation(double th) const { return rotation_y(scene.alpha_rad() + th); }

  void reset() {
    const Eigen::Matrix3d G = base_rotation(0.0);
    x.resize(3 * n);
    for (int i = 0; i < n; ++i) x.segment<3>(3 * i) = G * model->rest_positions.segment<3>(3 * i);
    v = Eigen::VectorXd::Zero(3 * n);
    v_prev = v;
    omega_last = 0.0;
    f = Eigen::VectorXd::Zero(3 * n);
    batch.set_all_rotations(G);
    t = 0.0;
    theta = theta_from = theta_to = 0.0;
    ramp_total = ramp_done = 0;
    pressures_Pa = {0.0, 0.0};
    z_touch = 1e300;
    for (int c : model->contact_nodes) z_touch = std::min(z_touch, x[3 * c + 2]);
    if (model->contact_nodes.empty()) z_touch = -1e9;
    z_mean = z_touch + scene.preload_mm;
    contacts.clear();
    was_active.assign(model->contact_nodes.size(), 0);
    broken = false;
    for (RefSlot& sl : slots) sl.use = RefSlot::Use::Rest;
  }

  double plate_at(double time) const {
    return z_mean + scene.plate_amplitude_mm * std::sin(scene.omega() * time + scene.plate_phase_rad);
  }

  // ---------------------------------------------------------------- forces
  // Total force at x (elastic + fibres + gravity + pressure) into f; rotations updated.
  // Returns false (with status) if an element is inverted or the state is not finite.
  // rotation_tolerance: accuracy of the polar rotations [rad] (1e-14 for the exact step; the
  // fast step uses 1e-6, a force error of the same relative size, far below its CG tolerance).
  StepStatus force_pass(const Eigen::VectorXd& xx, Eigen::VectorXd& ff, std::string& why,
                        const Eigen::VectorXd* u = nullptr, Eigen::VectorXd* ku = nullptr,
                        double rotation_tolerance = 1e-14) {
    ff.setZero(3 * n);
    if (u) ku->setZero(3 * n);
    double J = 0.0;
    if (const int e = batch.elastic_pass(xx, rotation_tolerance, ff, u, ku, &J); e >= 0) {
      why = std::isfinite(J) ? "inverted element " + std::to_string(e) + " (det F = " + std::to_string(J) + ")"
                             : "non-finite deformation in element " + std::to_string(e);
      return std::isfinite(J) ? StepStatus::InvertedElement : StepStatus::NonFinite;
    }
    fibre_kt.resize(model->fibres.size());
    for (std::size_t q = 0; q < model->fibres.size(); ++q) {
      const FibreSpring& s = model->fibres[q];
      fibre_kt[q] = fibre_tangent(*model, s, xx);  // cached for the mat-vecs of this step
      const Eigen::Vector3d fa = fibre_force(*model, s, xx);
      for (int a = 0; a < 4; ++a) {
        ff.segment<3>(3 * model->mesh.tets[s.a.tet][a]) += s.a.weights[a] * fa;
        ff.segment<3>(3 * model->mesh.tets[s.b.tet][a]) -= s.b.weights[a] * fa;
      }
    }
    if (u) add_fibre_K(*u, *ku);
    const double g = model->material.gravity_mm_s2;
    for (int i = 0; i < n; ++i) ff[3 * i + 2] -= model->lumped_mass[i] * g;
    add_pressure_forces(model->mesh, xx, pressures_Pa, ff);
    // A NaN load (e.g. a NaN pressure) must fail here: the fast step's CG convergence test
    // (‖r‖ > tol) is false for NaN, so it would return its finite warm start as if converged.
    if (!ff.allFinite()) {
      why = "non-finite forces (pressure/fibre/elastic/gravity load)";
      return StepStatus::NonFinite;
    }
    return StepStatus::Ok;
  }

  // y = K(x) u (co-rotated elastic + fibre tangents), all DOFs.
  void apply_K(const Eigen::VectorXd& u, Eigen::VectorXd& y) {
    y.setZero(3 * n);
    batch.add_stiffness_times(u, y);
    add_fibre_K(u, y);
  }

  // Fibre tangents (cached by the last force pass) times u.
  void add_fibre_K(const Eigen::VectorXd& u, Eigen::VectorXd& y) const {
    for (std::size_t q = 0; q < model->fibres.size(); ++q) {
      const FibreSpring& s = model->fibres[q];
      const Eigen::Matrix3d& kt = fibre_kt[q];
      if (kt.isZero(0.0)) continue;
      const Eigen::Vector3d du = embedded_position(model->mesh, s.a, u) - embedded_position(model->mesh, s.b, u);
      const Eigen::Vector3d fa = kt * du;
      for (int a = 0; a < 4; ++a) {
        y.segment<3>(3 * model->mesh.tets[s.a.tet][a]) += s.a.weights[a] * fa;
        y.segment<3>(3 * model->mesh.tets[s.b.tet][a]) -= s.b.weights[a] * fa;
      }
    }
  }

  // y = A u with A = c_m M + c_k K(x), all DOFs.
  void apply_A(const Eigen::VectorXd& u, double c_m, double c_k, Eigen::VectorXd& y) {
    apply_K(u, y);
    y *= c_k;
    for (int i = 0; i < n; ++i) y.segment<3>(3 * i) += c_m * model->lumped_mass[i] * u.segment<3>(3 * i);
  }

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

  bool build_exact(double dt) {
    double c_m, c_k;
    coefficients(dt, c_m, c_k);
    assemble_system(*model, free_index, batch.rotation_matrices(), x, c_m, c_k, *A);
    if (!exact_analysed) {
      exact_factor.analyse(A->dofs(), A->colptr(), A->rowind(), 3);
      exact_analysed = true;
    }
    ++factorisations;
    return exact_factor.factorise(A->values());
  }

  bool build_reference(Reference& ref, double dt) {
    double c_m, c_k;
    coefficients(dt, c_m, c_k);
    assemble_system(*model, free_index, batch.rotation_matrices(), x, c_m, c_k, *A);
    if (!ref.factor.size()) ref.factor.analyse(A->dofs(), A->colptr(), A->rowind(), 3);
    ++factorisations;
    ref.valid = ref.factor.factorise(A->values());
    if (!ref.valid) return false;
    ref.dt = dt;
    update_node_rotations();
    ref.node_rot = node_rot;
    const int m = static_cast<int>(model->contact_nodes.size());
    ref.cols.assign(m, {});
    return true;
  }

  // Node rotations: normalised volume-weighted sum of the adjacent element rotations as unit
  // quaternions (sign-aligned with the node's previous rotation) — a cheap rotation average;
  // it only shapes the preconditioner.
  void update_node_rotations() {
    if (static_cast<int>(node_qrot.size()) != nfree) node_qrot.assign(nfree, Eigen::Quaterniond(base_rotation(0.0)));
    std::vector<Eigen::Vector4d> acc(nfree, Eigen::Vector4d::Zero());
    const auto& tets = model->mesh.tets;
    for (std::size_t e = 0; e < tets.size(); ++e) {
      const Eigen::Vector4d qe = batch.quaternion(static_cast<int>(e)).coeffs() * model->rest[e].volume;
      for (int a = 0; a < 4; ++a)
        if (const int k = free_index[tets[e][a]]; k >= 0) acc[k] += qe.dot(node_qrot[k].coeffs()) >= 0.0 ? qe : Eigen::Vector4d(-qe);
    }
    node_rot.resize(nfree);
    for (int k = 0; k < nfree; ++k) {
      const double nrm = acc[k].norm();
      if (nrm > 0.0) node_qrot[k].coeffs() = acc[k] / nrm;
      node_rot[k] = node_qrot[k].toRotationMatrix();
    }
  }

  // Q_k = R_k(now) R_k(ref)ᵀ: how far each node's frame turned since the reference.
  void update_warp(const Reference& ref) {
    warp.resize(nfree);
    for (int k = 0; k < nfree; ++k) warp[k] = node_rot[k] * ref.node_rot[k].transpose();
  }

  // Makes sure the reference columns of candidate c exist.
  bool ensure_columns(Reference& ref, int c) {
    if (ref.cols[c][0].size() > 0) return true;
    const int k = free_index[model->contact_nodes[c]];
    Eigen::VectorXd e = Eigen::VectorXd::Zero(3 * nfree);
    for (int d = 0; d < 3; ++d) {
      e.setZero();
      e[3 * k + d] = 1.0;
      Eigen::VectorXd y(3 * nfree);
      ref.factor.solve(e.data(), y.data());
      if (!y.allFinite()) return false;
      ref.cols[c][d] = std::move(y);
    }
    return true;
  }

  RefSlot& slot(bool dynamic) { return slots[dynamic ? 0 : 1]; }

  // Force scale of the "force" stopping rule [µN]: the larger of ‖f‖ (the step's total force
  // on the free DOFs: elastic + fibres + gravity + pressure, i.e. the contact reactions when the
  // body is near balance) and the norm of the body's weight on the free DOFs (so an unloaded body
  // at rest keeps a finite scale). Neither depends on the velocities.
  double force_scale() const {
    double ff = 0.0, ww = 0.0;
    const double g = model->material.gravity_mm_s2;
    for (int i = 0; i < n; ++i) {
      if (free_index[i] < 0) continue;
      ff += f.segment<3>(3 * i).squaredNorm();
      ww += model->lumped_mass[i] * model->lumped_mass[i] * g * g;
    }
    return std::sqrt(std::max(ff, ww));
  }

  // y = Q A_ref⁻¹ Qᵀ r (free DOFs), Q = blockdiag(warp): the stored inverse turned node by node.
  void apply_ref_inverse(Reference& ref, const Eigen::VectorXd& r, Eigen::VectorXd& y) {
    work_u.resize(r.size());
    for (int k = 0; k < nfree; ++k) work_u.segment<3>(3 * k) = warp[k].transpose() * r.segment<3>(3 * k);
    y.resize(r.size());
    ref.factor.solve(work_u.data(), y.data());
    for (int k = 0; k < nfree; ++k) y.segment<3>(3 * k) = warp[k] * y.segment<3>(3 * k).eval();
  }

  StepResult fail(StepStatus s, std::string why) {
    broken = true;
    StepResult r;
    r.status = s;
    r.reason = std::move(why);
    return r;
  }

  // ---------------------------------------------------------------- the step
  StepResult advance(bool dynamic, std::optional<double> plate_override = std::nullopt) {
    if (broken) return fail(StepStatus::SolverFailure, "simulator is in a failed state; call reset()");
    const double dt = dynamic ? solver.dt_s : solver.static_dt_s;
    // Base angle for the end of the step.
    double theta_new = theta;
    if (ramp_done < ramp_total) {
      ++ramp_done;
      theta_new = theta_from + (theta_to - theta_from) * double(ramp_done) / ramp_total;
    }
    if (!dynamic && ramp_done < ramp_total) {  // static: go to the target at once
      ramp_done = ramp_total;
      theta_new = theta_to;
    }
    const double t_new = dynamic ? t + dt : t;
    const double plate_new = plate_override ? *plate_override : plate_at(t_new);

    std::string why;
    // Guess: free nodes keep their velocity (dynamic) or rest (static); base nodes prescribed;
    // (fast) contact nodes active in the last step land on the plate.
    const Eigen::Matrix3d Gb = base_rotation(theta_new);
    Eigen::VectorXd vg = dynamic ? v : Eigen::VectorXd::Zero(3 * n);
    // A change of the base's angular velocity carries the body along rigidly to first order.
    const double omega_new = dynamic ? (theta_new - theta) / dt : 0.0;
    if (dynamic && solver.method == StepMethod::Fast && omega_new != omega_last) {
      const Eigen::Vector3d dw(0.0, omega_new - omega_last, 0.0);
      for (int i = 0; i < n; ++i) vg.segment<3>(3 * i) += dw.cross(x.segment<3>(3 * i));
    }
    // The last step's velocity change is assumed to go on (linear extrapolation, including a
    // base turn's rigid change again, which measured best: 4.28 -> 3.70 CG iterations per step
    // under policy-like turns, `bench fem --turn-deg 5` on j41).
    if (dynamic && solver.method == StepMethod::Fast) vg += v - v_prev;
    for (int bn : model->base_nodes)
      vg.segment<3>(3 * bn) = (Gb * model->rest_positions.segment<3>(3 * bn) - x.segment<3>(3 * bn)) / dt;
    const bool exact = solver.method == StepMethod::Exact;
    if (!exact)
      for (std::size_t c = 0; c < model->contact_nodes.size(); ++c)
        if (was_active[c]) vg[3 * model->contact_nodes[c] + 2] = (plate_new - x[3 * model->contact_nodes[c] + 2]) / dt;
    Eigen::VectorXd kv;
    const StepStatus fs = exact ? force_pass(x, f, why) : force_pass(x, f, why, &vg, &kv, 1e-6);
    if (fs != StepStatus::Ok) return fail(fs, why);
    double c_m, c_k;
    coefficients(dt, c_m, c_k);
    // Right-hand side b = M v + dt f (all DOFs).
    Eigen::VectorXd b = dt * f;
    if (dynamic)
      for (int i = 0; i < n; ++i) b.segment<3>(3 * i) += model->lumped_mass[i] * v.segment<3>(3 * i);
    Eigen::VectorXd vnew;
    const StepResult sr = exact ? exact_solve(vg, b, plate_new, dt, c_m, c_k, vnew)
                                : fast_solve(vg, kv, b, plate_new, dt, c_m, c_k, vnew);
    if (!sr.ok()) return sr;
    // Update the state.
    Eigen::VectorXd xnew = x + dt * vnew;
    for (int bn : model->base_nodes) xnew.segment<3>(3 * bn) = Gb * model->rest_positions.segment<3>(3 * bn);
    if (!xnew.allFinite() || !vnew.allFinite()) return fail(StepStatus::NonFinite, "non-finite positions or velocities");
    x = std::move(xnew);
    v_prev = v;
    v = dynamic ? std::move(vnew) : Eigen::VectorXd::Zero(3 * n);
    t = t_new;
    omega_last = dynamic ? (theta_new - theta) / dt : 0.0;
    theta = theta_new;
    return sr;
  }

  // Exact: factorise A(x), free solve, then the contact LCP with exact Delassus columns.
  StepResult exact_solve(const Eigen::VectorXd& vg, const Eigen::VectorXd& b, double plate_new, double dt,
                         double c_m, double c_k, Eigen::VectorXd& vnew) {
    StepResult res;
    Eigen::VectorXd av, r;
    apply_A(vg, c_m, c_k, av);
    gather(b - av, r);
    if (!build_exact(dt)) return fail(StepStatus::SolverFailure, "CHOLMOD factorisation failed (matrix not positive definite)");
    Eigen::VectorXd dv(r.size());
    exact_factor.solve(r.data(), dv.data());
    res.iterations = 1;
    res.refactorised = true;
    Eigen::VectorXd vfree = vg;
    scatter_add(dv, vfree);

    contacts.clear();
    const auto& cn = model->contact_nodes;
    const int m = static_cast<int>(cn.size());
    std::vector<int> set;
    std::vector<char> in_set(m, 0);
    for (int c = 0; c < m; ++c) {
      const double zf = x[3 * cn[c] + 2] + dt * vfree[3 * cn[c] + 2];
      if (zf - plate_new < solver.contact_margin_mm || was_active[c]) set.push_back(c), in_set[c] = 1;
    }
    vnew = vfree;
    std::vector<char> active_now(m, 0);
    if (!set.empty()) {
      Eigen::MatrixXd cols;  // A⁻¹ e_z at each node of the set (free DOFs)
      Eigen::VectorXd lam;
      for (int round = 0; round < 8; ++round) {
        const int k = static_cast<int>(set.size());
        Eigen::MatrixXd B = Eigen::MatrixXd::Zero(3 * nfree, k);
        for (int a = 0; a < k; ++a) B(3 * free_index[cn[set[a]]] + 2, a) = 1.0;
        exact_factor.solve(B, cols);
        Eigen::MatrixXd D(k, k);
        Eigen::VectorXd g(k);
        std::vector<char> guess(k);
        for (int a = 0; a < k; ++a) {
          const int node = cn[set[a]];
          g[a] = x[3 * node + 2] + dt * vfree[3 * node + 2] - plate_new;
          guess[a] = was_active[set[a]];
          for (int bb = 0; bb < k; ++bb) D(a, bb) = dt * dt * cols(3 * free_index[node] + 2, bb);
        }
        D = 0.5 * (D + D.transpose()).eval();
        const LcpResult lcp = solve_contact_lcp(D, g, guess, 1e-9);
        if (!lcp.converged || !lcp.lambda.allFinite())
          return fail(StepStatus::ContactFailure, "contact LCP did not converge (violation " + std::to_string(lcp.max_violation) + " mm)");
        lam = lcp.lambda;
        vnew = vfree;
        const Eigen::VectorXd dvc = dt * (cols * lam);
        scatter_add(dvc, vnew);
        // Any candidate outside the set pushed through the plate? Add it and solve again.
        bool added = false;
        for (int c = 0; c < m; ++c) {
          if (in_set[c]) continue;
          const double z = x[3 * cn[c] + 2] + dt * vnew[3 * cn[c] + 2];
          if (z < plate_new - 1e-9) set.push_back(c), in_set[c] = 1, added = true;
        }
        if (!added) break;
      }
      for (std::size_t a = 0; a < set.size(); ++a)
        if (lam[a] > 0.0) {
          contacts.emplace_back(cn[set[a]], lam[a]);  // λ is the contact force [µN]
          active_now[set[a]] = 1;
        }
    }
    was_active = active_now;
    return res;
  }

  // Fast: constrained PCG (see simulator.hpp). Active contact nodes get their vertical velocity
  // prescribed so they land on the plate; the multiplier is the reaction at that DOF.
  // kvg = K(x) vg from the fused force pass (saves one mat-vec in the first round).
  StepResult fast_solve(const Eigen::VectorXd& vg, const Eigen::VectorXd& kvg, const Eigen::VectorXd& b,
                        double plate_new, double dt, double c_m, double c_k, Eigen::VectorXd& vnew) {
    StepResult res;
    RefSlot& sl = slot(dt == solver.dt_s);
    if (!sl.rest.valid) {
      // Built once at the reset placement (θ = 0, undeformed), kept across reset().
      // (Its node rotations come from the current quaternions, as they always have.)
      const Eigen::VectorXd xs = x;
      const CorotatedBatch::Rotations rs = batch.rotations();
      const double th = theta;
      const Eigen::Matrix3d G0 = base_rotation(0.0);
      for (int i = 0; i < n; ++i) x.segment<3>(3 * i) = G0 * model->rest_positions.segment<3>(3 * i);
      batch.set_all_rotation_matrices(G0);
      theta = 0.0;
      const bool ok = build_reference(sl.rest, dt);
      theta = th;
      x = xs;
      batch.set_rotations(rs);
      if (!ok) return fail(StepStatus::SolverFailure, "CHOLMOD factorisation of the reference matrix failed");
      res.refactorised = true;
    }
    Reference& ref = active(sl);
    update_node_rotations();
    update_warp(ref);
    const auto& cn = model->contact_nodes;
    const int m = static_cast<int>(cn.size());
    std::vector<char> active = was_active;
    vnew = vg;
    Eigen::VectorXd bf;
    gather(b, bf);
    const bool relative_stop = solver.fast_stop == FastStop::Relative;
    double scale = std::max(relative_stop ? bf.norm() : dt * force_scale(), 1e-300);
    double tol = solver.fast_tolerance * scale;
    Eigen::VectorXd av, r, rc, z, p, q, dall(3 * n), pz;
    int total_iterations = 0;
    Eigen::VectorXd lam_all = Eigen::VectorXd::Zero(m);
    for (int round = 0; round < 12; ++round) {
      std::vector<int> act;
      for (int c = 0; c < m; ++c)
        if (active[c]) act.push_back(c);
      const int k = static_cast<int>(act.size());
      std::vector<int> crow(k);  // constrained free-DOF rows
      for (int a = 0; a < k; ++a) {
        crow[a] = 3 * free_index[cn[act[a]]] + 2;
        vnew[3 * cn[act[a]] + 2] = (plate_new - x[3 * cn[act[a]] + 2]) / dt;
      }
      // C = P Jᵀ (free DOFs), JC = J P Jᵀ.
      Eigen::MatrixXd C(3 * nfree, k);
      for (int a = 0; a < k; ++a) {
        if (!ensure_columns(ref, act[a])) return fail(StepStatus::SolverFailure, "non-finite reference solve");
        const Eigen::Vector3d dz = warp[free_index[cn[act[a]]]].transpose() * Eigen::Vector3d::UnitZ();
        const auto& cc = ref.cols[act[a]];
        Eigen::VectorXd col = dz.x() * cc[0] + dz.y() * cc[1] + dz.z() * cc[2];
        for (int qq = 0; qq < nfree; ++qq) col.segment<3>(3 * qq) = warp[qq] * col.segment<3>(3 * qq).eval();
        C.col(a) = col;
      }
      Eigen::MatrixXd JC(k, k);
      for (int a = 0; a < k; ++a) JC.row(a) = C.row(crow[a]);
      const Eigen::LDLT<Eigen::MatrixXd> jc(0.5 * (JC + JC.transpose()));
      auto precondition = [&](const Eigen::VectorXd& in, Eigen::VectorXd& out) {
        apply_ref_inverse(ref, in, out);
        if (k == 0) return;
        Eigen::VectorXd jp(k);
        for (int a = 0; a < k; ++a) jp[a] = out[crow[a]];
        out -= C * jc.solve(jp);
        for (int a = 0; a < k; ++a) out[crow[a]] = 0.0;
      };
      auto project = [&](Eigen::VectorXd& w) {
        for (int a = 0; a < k; ++a) w[crow[a]] = 0.0;
      };
      // Residual of the current guess (unprojected: its constrained rows give the reactions).
      if (round == 0) {
        av = c_k * kvg;
        for (int i = 0; i < n; ++i) av.segment<3>(3 * i) += c_m * model->lumped_mass[i] * vnew.segment<3>(3 * i);
      } else {
        apply_A(vnew, c_m, c_k, av);
      }
      gather(b - av, r);
      rc = r;
      project(rc);
      Eigen::VectorXd dvf = Eigen::VectorXd::Zero(3 * nfree);
      const double r0n = rc.norm();
      if (relative_stop && round == 0 && r0n > scale) {  // residual reduction relative to max(‖b‖, ‖r0‖)
        scale = r0n;
        tol = solver.fast_tolerance * scale;
      }
      double rz = 0.0;
      int it = 0;
      // Preconditioned CG; the convergence test comes before the preconditioner, so a converged
      // residual costs no further solve.
      while (rc.norm() > tol && it < solver.fast_max_iterations) {
        precondition(rc, z);
        const double rz_new = rc.dot(z);
        if (it == 0) p = z;
        else p = z + (rz_new / rz) * p;
        rz = rz_new;
        dall.setZero();
        scatter_add(p, dall);
        apply_A(dall, c_m, c_k, av);
        gather(av, q);
        const double pq = p.dot(q);
        if (!(pq > 0.0)) break;
        const double alpha = rz / pq;
        dvf += alpha * p;
        r -= alpha * q;
        rc = r;
        project(rc);
        ++it;
      }
      total_iterations += it;
      res.residual_force_uN = rc.norm() / dt;
      scatter_add(dvf, vnew);
      if (!vnew.allFinite()) return fail(StepStatus::NonFinite, "non-finite velocity in the fast solve");
      // Multipliers: A v = b + dt Jᵀλ  ⇒  λ = −r_constrained / dt.
      lam_all.setZero();
      int release = -1;
      double most_negative = 0.0;
      for (int a = 0; a < k; ++a) {
        lam_all[act[a]] = -r[crow[a]] / dt;
        if (lam_all[act[a]] < most_negative) most_negative = lam_all[act[a]], release = act[a];
      }
      if (release >= 0) {
        active[release] = 0;
        continue;
      }
      int add = -1;
      double deepest = -solver.contact_tolerance_mm;
      for (int c = 0; c < m; ++c) {
        if (active[c]) continue;
        const double gap = x[3 * cn[c] + 2] + dt * vnew[3 * cn[c] + 2] - plate_new;
        if (gap < deepest) deepest = gap, add = c;
      }
      if (add >= 0) {
        active[add] = 1;
        continue;
      }
      break;
    }
    contacts.clear();
    for (int c = 0; c < m; ++c)
      if (active[c] && lam_all[c] > 0.0) contacts.emplace_back(cn[c], lam_all[c]);
    was_active = active;
    res.iterations = total_iterations;
    if (total_iterations > solver.fast_refactor_iterations) {
      // The stored factor has drifted from the current matrix: refactorise at this state.
      if (!build_reference(sl.cur, dt)) return fail(StepStatus::SolverFailure, "CHOLMOD refactorisation failed");
      sl.use = RefSlot::Use::Cur;
      res.refactorised = true;
    }
    return res;
  }
};

// ---------------------------------------------------------------- snapshots
struct Simulator::Snapshot::Data {
  const Model* model = nullptr;
  Eigen::VectorXd x, v, f, v_prev;
  double omega_last = 0.0;
  CorotatedBatch::Rotations rotations;
  std::vector<Eigen::Matrix3d> fibre_kt;
  double t = 0.0, theta = 0.0, theta_from = 0.0, theta_to = 0.0;
  int ramp_total = 0, ramp_done = 0;
  std::vector<double> pressures_Pa;
  double z_touch = 0.0, z_mean = 0.0, plate_phase_rad = 0.0;
  std::vector<std::pair<int, double>> contacts;
  std::vector<char> was_active;
  std::vector<Eigen::Quaterniond> node_qrot;
  std::vector<Eigen::Matrix3d> node_rot;
  bool dynamic_cur = false;  // the dynamic step had a factor at a deformed state
  // Set when that factor was the one built by settle(): restore() into the same simulator then
  // reuses it while the simulator still holds it (same token).
  std::shared_ptr<const int> settled_token;
};

// ---------------------------------------------------------------- public wrapper
Simulator::Simulator(std::shared_ptr<const Model> model, const SceneConfig& scene, const SolverConfig& solver)
    : impl_(std::make_unique<Impl>(std::move(model), scene, solver)) {}
Simulator::~Simulator() = default;
Simulator::Simulator(Simulator&&) noexcept = default;
Simulator& Simulator::operator=(Simulator&&) noexcept = default;

void Simulator::reset() { impl_->reset(); }

StepResult Simulator::settle(SettleFor purpose) {
  Impl& m = *impl_;
  StepResult last;
  const int n = std::max(1, m.scene.settle_steps);
  for (int s = 1; s <= n; ++s) {
    last = m.advance(false, m.z_touch + (m.plate_at(0.0) - m.z_touch) * double(s) / n);
    if (!last.ok()) return last;
  }
  // A few extra static iterations at the final height.
  for (int s = 0; s < 5; ++s) {
    last = m.advance(false);
    if (!last.ok()) return last;
  }
  // Fast: factorise the dynamic system at the settled state — the operating point of the
  // episode is a far better preconditioner than the straight rest placement. A settle for a
  // reading leaves no dynamic step to precondition.
  if (m.solver.method == StepMethod::Fast && purpose == SettleFor::Episode) {
    std::string why;
    Eigen::VectorXd ff;
    const StepStatus fs = m.force_pass(m.x, ff, why);
    if (fs != StepStatus::Ok) return m.fail(fs, why);
    Impl::RefSlot& sl = m.slot(true);
    m.settled_token.reset();
    if (!m.build_reference(m.settled, m.solver.dt_s)) return m.fail(StepStatus::SolverFailure, "CHOLMOD factorisation at the settled state failed");
    m.settled_token = std::make_shared<const int>(0);
    sl.use = Impl::RefSlot::Use::Settled;
    last.refactorised = true;
  }
  // Dynamic time starts at t = 0 with the plate at z0 + U sin(phase).
  return last;
}

StepResult Simulator::static_step() { return impl_->advance(false); }
StepResult Simulator::step() { return impl_->advance(true); }

void Simulator::set_pressures_kPa(double p0, double p1) {
  impl_->pressures_Pa = {1e3 * p0, impl_->model->chamber_count() >= 2 ? 1e3 * p1 : 0.0};
}

void Simulator::set_base_angle_target(double theta_rad, int n_substeps) {
  Impl& m = *impl_;
  m.theta_from = m.theta;
  m.theta_to = theta_rad;
  m.ramp_total = std::max(1, n_substeps);
  m.ramp_done = 0;
}

void Simulator::set_base_angle(double theta_rad) { set_base_angle_target(theta_rad, 1); }

void Simulator::set_plate_mean_z(double z0_mm) { impl_->z_mean = z0_mm; }

void Simulator::set_plate_phase(double phase_rad) { impl_->scene.plate_phase_rad = phase_rad; }

Simulator::Snapshot Simulator::snapshot() const {
  const Impl& m = *impl_;
  auto d = std::make_shared<Snapshot::Data>();
  d->model = m.model.get();
  d->x = m.x, d->v = m.v, d->f = m.f, d->v_prev = m.v_prev;
  d->omega_last = m.omega_last;
  d->rotations = m.batch.rotations(), d->fibre_kt = m.fibre_kt;
  d->t = m.t, d->theta = m.theta, d->theta_from = m.theta_from, d->theta_to = m.theta_to;
  d->ramp_total = m.ramp_total, d->ramp_done = m.ramp_done;
  d->pressures_Pa = m.pressures_Pa;
  d->z_touch = m.z_touch, d->z_mean = m.z_mean, d->plate_phase_rad = m.scene.plate_phase_rad;
  d->contacts = m.contacts, d->was_active = m.was_active;
  d->node_qrot = m.node_qrot, d->node_rot = m.node_rot;
  d->dynamic_cur = m.slots[0].use != Impl::RefSlot::Use::Rest;
  if (m.slots[0].use == Impl::RefSlot::Use::Settled) d->settled_token = m.settled_token;
  Snapshot s;
  s.data_ = std::move(d);
  return s;
}

StepResult Simulator::restore(const Snapshot& snapshot) {
  if (!snapshot.data_) throw std::invalid_argument("Simulator::restore: empty snapshot");
  const Snapshot::Data& d = *snapshot.data_;
  Impl& m = *impl_;
  if (d.model != m.model.get()) throw std::invalid_argument("Simulator::restore: snapshot of another model");
  m.x = d.x, m.v = d.v, m.f = d.f, m.v_prev = d.v_prev;
  m.omega_last = d.omega_last;
  m.batch.set_rotations(d.rotations);
  m.fibre_kt = d.fibre_kt;
  m.t = d.t, m.theta = d.theta, m.theta_from = d.theta_from, m.theta_to = d.theta_to;
  m.ramp_total = d.ramp_total, m.ramp_done = d.ramp_done;
  m.pressures_Pa = d.pressures_Pa;
  m.z_touch = d.z_touch, m.z_mean = d.z_mean, m.scene.plate_phase_rad = d.plate_phase_rad;
  m.contacts = d.contacts, m.was_active = d.was_active;
  m.node_qrot = d.node_qrot, m.node_rot = d.node_rot;
  m.broken = false;
  for (Impl::RefSlot& sl : m.slots) sl.use = Impl::RefSlot::Use::Rest;
  StepResult r;
  if (m.solver.method == StepMethod::Fast && d.settled_token && d.settled_token == m.settled_token) {
    // The factor settle() built at exactly this state is still here: the same matrix, so the
    // same factor a refactorisation would give (bit-identical), without its cost.
    m.slots[0].use = Impl::RefSlot::Use::Settled;
  } else if (m.solver.method == StepMethod::Fast && d.dynamic_cur) {
    // The factor depends only on x and the element rotations (restored above), as at the end
    // of settle(); the node rotations it stores come from the restored quaternions.
    Impl::RefSlot& sl = m.slot(true);
    if (!m.build_reference(sl.cur, m.solver.dt_s))
      return m.fail(StepStatus::SolverFailure, "CHOLMOD factorisation at the restored state failed");
    sl.use = Impl::RefSlot::Use::Cur;
    r.refactorised = true;
  }
  return r;
}

Sensors Simulator::sensors() const {
  const Impl& m = *impl_;
  Sensors s;
  s.time_s = m.t;
  s.theta_rad = m.theta;
  double F = 0.0;
  for (const auto& c : m.contacts) F += c.second;
  s.contact_force_mN = 1e-3 * F;
  s.active_contacts = static_cast<int>(m.contacts.size());
  s.in_contact = F > 0.0;
  s.theta_extreme = std::abs(m.theta) > m.scene.theta_limit_deg * std::numbers::pi / 180.0;
  s.plate_z_mm = m.plate_at(m.t);
  const Model& md = *m.model;
  double acc = 0.0;
  for (int e : md.chamber_tets) {
    const Tet& tt = md.mesh.tets[e];
    const std::array<Eigen::Vector3d, 4> xe{m.x.segment<3>(3 * tt[0]), m.x.segment<3>(3 * tt[1]),
                                            m.x.segment<3>(3 * tt[2]), m.x.segment<3>(3 * tt[3])};
    const Eigen::Matrix3d F = deformation_gradient(md.rest[e], xe);
    acc += md.rest[e].volume * (F.col(0).norm() - 1.0);
  }
  s.axial_strain = md.chamber_volume_mm3 > 0.0 ? acc / md.chamber_volume_mm3 : 0.0;
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();
  for (int i : md.tip_nodes) tip += m.x.segment<3>(3 * i);
  s.tip_position_mm = tip / std::max<std::size_t>(1, md.tip_nodes.size());
  return s;
}

std::vector<double> Simulator::element_axial_strain() const {
  const Impl& m = *impl_;
  const Model& md = *m.model;
  std::vector<double> out(md.mesh.tets.size());
  for (std::size_t e = 0; e < out.size(); ++e) {
    const Tet& tt = md.mesh.tets[e];
    const std::array<Eigen::Vector3d, 4> xe{m.x.segment<3>(3 * tt[0]), m.x.segment<3>(3 * tt[1]),
                                            m.x.segment<3>(3 * tt[2]), m.x.segment<3>(3 * tt[3])};
    out[e] = deformation_gradient(md.rest[e], xe).col(0).norm() - 1.0;
  }
  return out;
}

double Simulator::time() const { return impl_->t; }
double Simulator::theta() const { return impl_->theta; }
double Simulator::plate_z() const { return impl_->plate_at(impl_->t); }
double Simulator::plate_touch_z() const { return impl_->z_touch; }
const Eigen::VectorXd& Simulator::positions() const { return impl_->x; }
const Eigen::VectorXd& Simulator::velocities() const { return impl_->v; }
const std::vector<std::pair<int, double>>& Simulator::contact_forces() const { return impl_->contacts; }

Eigen::Vector3d Simulator::base_reaction() const {
  Impl& m = *impl_;
  Eigen::VectorXd ff;
  std::string why;
  const CorotatedBatch::Rotations keep = m.batch.rotations();
  const std::vector<Eigen::Matrix3d> keepk = m.fibre_kt;
  m.force_pass(m.x, ff, why);  // the caches (rotations, fibre tangents) stay those of the step
  m.batch.set_rotations(keep);
  m.fibre_kt = keepk;
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  for (int b : m.model->base_nodes) r -= ff.segment<3>(3 * b);
  return r;
}

Eigen::Vector3d Simulator::pressure_force() const {
  const Impl& m = *impl_;
  Eigen::VectorXd ff = Eigen::VectorXd::Zero(3 * m.n);
  add_pressure_forces(m.model->mesh, m.x, m.pressures_Pa, ff);
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  for (int i = 0; i < m.n; ++i) s += ff.segment<3>(3 * i);
  return s;
}

const Model& Simulator::model() const { return *impl_->model; }
const SceneConfig& Simulator::scene() const { return impl_->scene; }
const SolverConfig& Simulator::solver() const { return impl_->solver; }
int Simulator::factorisations() const { return impl_->factorisations; }

}  // namespace codesign::fem
