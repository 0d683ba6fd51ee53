#include "fem/simulator_impl.hpp"

#include <algorithm>

#include <Eigen/Dense>

namespace codesign::fem {

StepResult Simulator::Impl::fast_solve(const Eigen::VectorXd& vg, const Eigen::VectorXd& kvg, const Eigen::VectorXd& b,
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

}  // namespace codesign::fem
