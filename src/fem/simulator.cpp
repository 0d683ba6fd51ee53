#include "fem/simulator.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "fem/cholmod_factor.hpp"
#include "fem/contact.hpp"
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

// A stored factorisation of A at base angle theta_ref (world frame), used by the fast method.
struct Reference {
  CholmodFactor factor;
  double theta_ref = 0.0;
  double dt = 0.0;
  // A_ref⁻¹ e for unit loads in world x and z at every contact candidate (free-DOF vectors).
  Eigen::MatrixXd cols_x, cols_z;
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
  Eigen::VectorXd x, v, f;   // f: total force at x from the last force pass (µN)
  std::vector<Eigen::Matrix3d> rot;
  double t = 0.0;
  double theta = 0.0, theta_from = 0.0, theta_to = 0.0;
  int ramp_total = 0, ramp_done = 0;
  std::vector<double> pressures_Pa{0.0, 0.0};
  double z_touch = 0.0, z_mean = 0.0;
  std::vector<std::pair<int, double>> contacts;
  std::vector<char> was_active;  // per contact candidate
  bool broken = false;
  int factorisations = 0;
  int steps_since_check = 0;

  // Exact machinery (also used to build references).
  std::optional<SystemMatrix> A;
  CholmodFactor exact_factor;
  bool exact_analysed = false;
  // Fast machinery.
  Reference rest_ref, cur_ref;  // rest_ref: at reset state; cur_ref: refactorised later
  bool use_cur = false;
  Eigen::VectorXd work_b, work_r, work_u, work_y;

  Impl(std::shared_ptr<const Model> m, const SceneConfig& sc, const SolverConfig& so)
      : model(std::move(m)), scene(sc), solver(so) {
    n = model->node_count();
    free_index.assign(n, -1);
    for (int i = 0; i < n; ++i)
      if (!model->is_base[i]) free_index[i] = nfree++, free_nodes.push_back(i);
    mu = model->material.lame_mu();
    lambda = model->material.lame_lambda();
    A.emplace(*model, free_index);
    reset();
  }

  Eigen::Matrix3d base_rotation(double th) const { return rotation_y(scene.alpha_rad() + th); }

  void reset() {
    const Eigen::Matrix3d G = base_rotation(0.0);
    x.resize(3 * n);
    for (int i = 0; i < n; ++i) x.segment<3>(3 * i) = G * model->rest_positions.segment<3>(3 * i);
    v = Eigen::VectorXd::Zero(3 * n);
    f = Eigen::VectorXd::Zero(3 * n);
    rot.assign(model->mesh.tets.size(), G);
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
    use_cur = false;
    steps_since_check = 0;
  }

  double plate_at(double time) const {
    return z_mean + scene.plate_amplitude_mm * std::sin(scene.omega() * time + scene.plate_phase_rad);
  }

  // ---------------------------------------------------------------- forces
  // Total force at x (elastic + fibres + gravity + pressure) into f; rotations updated.
  // Returns false (with status) if an element is inverted or the state is not finite.
  StepStatus force_pass(const Eigen::VectorXd& xx, Eigen::VectorXd& ff, std::string& why) {
    ff.setZero(3 * n);
    const auto& tets = model->mesh.tets;
    for (std::size_t e = 0; e < tets.size(); ++e) {
      const Tet& tt = tets[e];
      const std::array<Eigen::Vector3d, 4> xe{xx.segment<3>(3 * tt[0]), xx.segment<3>(3 * tt[1]),
                                              xx.segment<3>(3 * tt[2]), xx.segment<3>(3 * tt[3])};
      const Eigen::Matrix3d F = deformation_gradient(model->rest[e], xe);
      const double J = F.determinant();
      if (!(J > 0.0)) {
        why = std::isfinite(J) ? "inverted element " + std::to_string(e) + " (det F = " + std::to_string(J) + ")"
                               : "non-finite deformation in element " + std::to_string(e);
        return std::isfinite(J) ? StepStatus::InvertedElement : StepStatus::NonFinite;
      }
      rot[e] = polar_rotation(F, rot[e]);
      const Vec12 fe = corotated_force(model->rest[e], F, rot[e], mu, lambda);
      for (int a = 0; a < 4; ++a) ff.segment<3>(3 * tt[a]) += fe.segment<3>(3 * a);
    }
    for (const FibreSpring& s : model->fibres) {
      const Eigen::Vector3d d = embedded_position(model->mesh, s.a, xx) - embedded_position(model->mesh, s.b, xx);
      const double len = d.norm();
      if (!(len > s.rest_length_mm)) continue;
      const Eigen::Vector3d fa = -s.stiffness_uN_per_mm * (len - s.rest_length_mm) * (d / len);
      for (int a = 0; a < 4; ++a) {
        ff.segment<3>(3 * model->mesh.tets[s.a.tet][a]) += s.a.weights[a] * fa;
        ff.segment<3>(3 * model->mesh.tets[s.b.tet][a]) -= s.b.weights[a] * fa;
      }
    }
    const double g = model->material.gravity_mm_s2;
    for (int i = 0; i < n; ++i) ff[3 * i + 2] -= model->lumped_mass[i] * g;
    add_pressure_forces(model->mesh, xx, pressures_Pa, ff);
    return StepStatus::Ok;
  }

  // y = K(x) u (co-rotated elastic + fibre tangents), all DOFs.
  void apply_K(const Eigen::VectorXd& u, Eigen::VectorXd& y) const {
    y.setZero(3 * n);
    const auto& tets = model->mesh.tets;
    for (std::size_t e = 0; e < tets.size(); ++e) {
      const Tet& tt = tets[e];
      Vec12 ue;
      for (int a = 0; a < 4; ++a) ue.segment<3>(3 * a) = u.segment<3>(3 * tt[a]);
      const Vec12 ye = corotated_stiffness_times(model->rest[e], rot[e], ue, mu, lambda);
      for (int a = 0; a < 4; ++a) y.segment<3>(3 * tt[a]) += ye.segment<3>(3 * a);
    }
    for (const FibreSpring& s : model->fibres) {
      const Eigen::Matrix3d kt = fibre_tangent(*model, s, x);
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
  void apply_A(const Eigen::VectorXd& u, double c_m, double c_k, Eigen::VectorXd& y) const {
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
    assemble_system(*model, free_index, rot, x, c_m, c_k, *A);
    if (!exact_analysed) {
      exact_factor.analyse(A->dofs(), A->colptr(), A->rowind());
      exact_analysed = true;
    }
    ++factorisations;
    return exact_factor.factorise(A->values());
  }

  bool build_reference(Reference& ref, double dt) {
    double c_m, c_k;
    coefficients(dt, c_m, c_k);
    assemble_system(*model, free_index, rot, x, c_m, c_k, *A);
    if (!ref.factor.size()) ref.factor.analyse(A->dofs(), A->colptr(), A->rowind());
    ++factorisations;
    ref.valid = ref.factor.factorise(A->values());
    if (!ref.valid) return false;
    ref.theta_ref = theta;
    ref.dt = dt;
    const int m = static_cast<int>(model->contact_nodes.size());
    Eigen::MatrixXd B = Eigen::MatrixXd::Zero(3 * nfree, 2 * m);
    for (int c = 0; c < m; ++c) {
      const int k = free_index[model->contact_nodes[c]];
      B(3 * k + 0, c) = 1.0;
      B(3 * k + 2, m + c) = 1.0;
    }
    Eigen::MatrixXd X;
    ref.factor.solve(B, X);
    ref.cols_x = X.leftCols(m);
    ref.cols_z = X.rightCols(m);
    return X.allFinite();
  }

  Reference& reference() { return use_cur ? cur_ref : rest_ref; }

  // y = G A_ref⁻¹ Gᵀ r (free DOFs), G = blockdiag(R_y(θ − θ_ref)).
  void apply_ref_inverse(Reference& ref, const Eigen::VectorXd& r, Eigen::VectorXd& y) {
    const Eigen::Matrix3d G = rotation_y(theta - ref.theta_ref);
    work_u.resize(r.size());
    for (int k = 0; k < nfree; ++k) work_u.segment<3>(3 * k) = G.transpose() * r.segment<3>(3 * k);
    y.resize(r.size());
    ref.factor.solve(work_u.data(), y.data());
    for (int k = 0; k < nfree; ++k) y.segment<3>(3 * k) = G * y.segment<3>(3 * k).eval();
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

    StepResult res;
    std::string why;
    const StepStatus fs = force_pass(x, f, why);
    if (fs != StepStatus::Ok) return fail(fs, why);

    // Guess: free nodes keep their velocity (dynamic) or rest (static); base nodes prescribed.
    const Eigen::Matrix3d Gb = base_rotation(theta_new);
    Eigen::VectorXd vg = dynamic ? v : Eigen::VectorXd::Zero(3 * n);
    for (int b : model->base_nodes)
      vg.segment<3>(3 * b) = (Gb * model->rest_positions.segment<3>(3 * b) - x.segment<3>(3 * b)) / dt;
    double c_m, c_k;
    coefficients(dt, c_m, c_k);
    // b = M v + dt f, residual r = b − A vg on the free DOFs.
    Eigen::VectorXd av;
    apply_A(vg, c_m, c_k, av);
    Eigen::VectorXd rall = dt * f - av;
    if (dynamic)
      for (int i = 0; i < n; ++i) rall.segment<3>(3 * i) += model->lumped_mass[i] * v.segment<3>(3 * i);
    Eigen::VectorXd r;
    gather(rall, r);
    Eigen::VectorXd dv;
    const bool exact = solver.method == StepMethod::Exact || !dynamic;
    if (exact) {
      if (!build_exact(dt)) return fail(StepStatus::SolverFailure, "CHOLMOD factorisation failed (matrix not positive definite)");
      dv.resize(r.size());
      exact_factor.solve(r.data(), dv.data());
      res.iterations = 1;
      res.refactorised = true;
    } else {
      if (!rest_ref.valid) {
        // The rest reference is built at the reset placement (θ = 0, undeformed).
        const Eigen::VectorXd xs = x;
        const auto rs = rot;
        const Eigen::Matrix3d G0 = base_rotation(0.0);
        for (int i = 0; i < n; ++i) x.segment<3>(3 * i) = G0 * model->rest_positions.segment<3>(3 * i);
        std::fill(rot.begin(), rot.end(), G0);
        const double th = theta;
        theta = 0.0;
        const bool ok = build_reference(rest_ref, dt);
        theta = th;
        x = xs;
        rot = rs;
        if (!ok) return fail(StepStatus::SolverFailure, "CHOLMOD factorisation of the reference matrix failed");
        res.refactorised = true;
      }
      Reference& ref = reference();
      apply_ref_inverse(ref, r, dv);
      res.iterations = 1;
      const bool check = solver.fast_check_every > 0 && ++steps_since_check >= solver.fast_check_every;
      const int iters = std::max(1, solver.fast_iterations) + (check ? 1 : 0);
      Eigen::VectorXd dall(3 * n), adv, rr, ddv;
      double r0 = r.norm(), rk = r0;
      for (int it = 1; it < iters; ++it) {
        dall.setZero();
        scatter_add(dv, dall);
        apply_A(dall, c_m, c_k, adv);
        gather(adv, rr);
        rr = r - rr;  // residual of the current dv
        rk = rr.norm();
        if (check && it == iters - 1) break;  // only measured, not applied
        apply_ref_inverse(ref, rr, ddv);
        dv += ddv;
        ++res.iterations;
      }
      if (check) {
        steps_since_check = 0;
        const double contraction = r0 > 0.0 ? std::pow(rk / r0, 1.0 / std::max(1, solver.fast_iterations)) : 0.0;
        if (contraction > solver.fast_refactor_residual) {
          // Refactorise at the current state; this step is then solved with the new factor.
          if (!build_reference(cur_ref, dt)) return fail(StepStatus::SolverFailure, "CHOLMOD refactorisation failed");
          use_cur = true;
          res.refactorised = true;
          apply_ref_inverse(cur_ref, r, dv);
        }
      }
    }
    // Free velocity.
    Eigen::VectorXd vfree = vg;
    scatter_add(dv, vfree);

    // Contact.
    contacts.clear();
    const auto& cn = model->contact_nodes;
    const int m = static_cast<int>(cn.size());
    std::vector<int> set;
    std::vector<char> in_set(m, 0);
    for (int c = 0; c < m; ++c) {
      const double zf = x[3 * cn[c] + 2] + dt * vfree[3 * cn[c] + 2];
      if (zf - plate_new < solver.contact_margin_mm || was_active[c]) set.push_back(c), in_set[c] = 1;
    }
    Eigen::VectorXd vnew = vfree;
    std::vector<char> active_now(m, 0);
    if (!set.empty()) {
      // Columns of A⁻¹ for a unit upward load at each node of the set (free DOFs).
      Eigen::MatrixXd cols;
      Eigen::VectorXd lam;
      for (int round = 0; round < 8; ++round) {
        const int k = static_cast<int>(set.size());
        cols.resize(3 * nfree, k);
        if (exact) {
          Eigen::MatrixXd B = Eigen::MatrixXd::Zero(3 * nfree, k);
          for (int a = 0; a < k; ++a) B(3 * free_index[cn[set[a]]] + 2, a) = 1.0;
          exact_factor.solve(B, cols);
        } else {
          Reference& ref = reference();
          const Eigen::Matrix3d G = rotation_y(theta - ref.theta_ref);
          const Eigen::Vector3d d = G.transpose() * Eigen::Vector3d::UnitZ();  // e_z in the ref frame
          for (int a = 0; a < k; ++a) {
            Eigen::VectorXd col = d.x() * ref.cols_x.col(set[a]) + d.z() * ref.cols_z.col(set[a]);
            for (int q = 0; q < nfree; ++q) col.segment<3>(3 * q) = G * col.segment<3>(3 * q).eval();
            cols.col(a) = col;
          }
        }
        Eigen::MatrixXd D(k, k);
        Eigen::VectorXd g(k);
        std::vector<char> guess(k);
        for (int a = 0; a < k; ++a) {
          const int node = cn[set[a]];
          g[a] = x[3 * node + 2] + dt * vfree[3 * node + 2] - plate_new;
          guess[a] = was_active[set[a]];
          for (int b = 0; b < k; ++b) D(a, b) = dt * dt * cols(3 * free_index[node] + 2, b);
        }
        D = 0.5 * (D + D.transpose()).eval();
        const LcpResult lcp = solve_contact_lcp(D, g, guess, 1e-9);
        if (!lcp.converged || !lcp.lambda.allFinite())
          return fail(StepStatus::ContactFailure, "contact LCP did not converge (violation " + std::to_string(lcp.max_violation) + " mm)");
        lam = lcp.lambda;
        vnew = vfree;
        Eigen::VectorXd dvc = dt * (cols * lam);
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

    // Update the state.
    Eigen::VectorXd xnew = x + dt * vnew;
    for (int b : model->base_nodes) xnew.segment<3>(3 * b) = Gb * model->rest_positions.segment<3>(3 * b);
    if (!xnew.allFinite() || !vnew.allFinite()) return fail(StepStatus::NonFinite, "non-finite positions or velocities");
    x = std::move(xnew);
    v = dynamic ? std::move(vnew) : Eigen::VectorXd::Zero(3 * n);
    t = t_new;
    theta = theta_new;
    return res;
  }
};

// ---------------------------------------------------------------- public wrapper
Simulator::Simulator(std::shared_ptr<const Model> model, const SceneConfig& scene, const SolverConfig& solver)
    : impl_(std::make_unique<Impl>(std::move(model), scene, solver)) {}
Simulator::~Simulator() = default;
Simulator::Simulator(Simulator&&) noexcept = default;
Simulator& Simulator::operator=(Simulator&&) noexcept = default;

void Simulator::reset() { impl_->reset(); }

StepResult Simulator::settle() {
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
  std::vector<Eigen::Matrix3d> keep = m.rot;
  m.force_pass(m.x, ff, why);
  m.rot = keep;
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
