#include "fem/contact.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

namespace codesign::fem {

namespace {

double violation(const Eigen::MatrixXd& D, const Eigen::VectorXd& g, const Eigen::VectorXd& lam) {
  const Eigen::VectorXd w = g + D * lam;
  double v = 0.0;
  for (int i = 0; i < g.size(); ++i) {
    v = std::max(v, -w[i]);
    if (lam[i] > 0.0) v = std::max(v, std::abs(w[i]));
  }
  return v;
}

}  // namespace

LcpResult solve_contact_lcp(const Eigen::MatrixXd& D, const Eigen::VectorXd& g,
                            const std::vector<char>& active_guess, double gap_tol) {
  const int m = static_cast<int>(g.size());
  LcpResult res;
  res.lambda = Eigen::VectorXd::Zero(m);
  if (m == 0) {
    res.converged = true;
    return res;
  }
  std::vector<char> active(m, 0);
  for (int i = 0; i < m; ++i) active[i] = (i < static_cast<int>(active_guess.size()) && active_guess[i]) || g[i] < 0.0;
  const int cap = 10 * m + 20;
  for (int it = 0; it < cap; ++it) {
    res.iterations = it + 1;
    std::vector<int> idx;
    for (int i = 0; i < m; ++i)
      if (active[i]) idx.push_back(i);
    Eigen::VectorXd lam = Eigen::VectorXd::Zero(m);
    if (!idx.empty()) {
      const int k = static_cast<int>(idx.size());
      Eigen::MatrixXd daa(k, k);
      Eigen::VectorXd ga(k);
      for (int a = 0; a < k; ++a) {
        ga[a] = -g[idx[a]];
        for (int b = 0; b < k; ++b) daa(a, b) = D(idx[a], idx[b]);
      }
      Eigen::LDLT<Eigen::MatrixXd> ldlt(daa);
      const Eigen::VectorXd la = ldlt.solve(ga);
      for (int a = 0; a < k; ++a) lam[idx[a]] = la[a];
    }
    // Release the most negative multiplier first.
    int worst = -1;
    double wv = 0.0;
    for (int i = 0; i < m; ++i)
      if (active[i] && lam[i] < wv) wv = lam[i], worst = i;
    if (worst >= 0) {
      active[worst] = 0;
      continue;
    }
    const Eigen::VectorXd w = g + D * lam;
    worst = -1;
    wv = -gap_tol;
    for (int i = 0; i < m; ++i)
      if (!active[i] && w[i] < wv) wv = w[i], worst = i;
    if (worst >= 0) {
      active[worst] = 1;
      continue;
    }
    res.lambda = lam;
    res.converged = true;
    res.max_violation = violation(D, g, lam);
    return res;
  }
  // Fallback: projected Gauss–Seidel from zero.
  Eigen::VectorXd lam = Eigen::VectorXd::Zero(m);
  for (int sweep = 0; sweep < 5000; ++sweep) {
    for (int i = 0; i < m; ++i) {
      const double wi = g[i] + D.row(i).dot(lam);
      lam[i] = std::max(0.0, lam[i] - wi / D(i, i));
    }
  }
  res.lambda = lam;
  res.max_violation = violation(D, g, lam);
  res.converged = res.max_violation <= 10.0 * gap_tol;
  return res;
}

}  // namespace codesign::fem
