#include "fem/simulator_impl.hpp"

#include <Eigen/Dense>

#include "fem/contact.hpp"

namespace codesign::fem {

StepResult Simulator::Impl::exact_solve(const Eigen::VectorXd& vg, const Eigen::VectorXd& b, double plate_new, double dt,
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

}  // namespace codesign::fem
