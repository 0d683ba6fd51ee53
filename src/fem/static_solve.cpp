#include "fem/static_solve.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/CholmodSupport>
#include <Eigen/Geometry>
#include <Eigen/LU>

#include "fem/corotational_tet.hpp"
#include "fem/pressure.hpp"

namespace codesign::fem {

namespace {

using SpMat = Eigen::SparseMatrix<double>;

std::array<Eigen::Vector3d, 4> element_positions(const Model& model, int e, const Eigen::VectorXd& x) {
  const Tet& t = model.mesh.tets[static_cast<std::size_t>(e)];
  return {x.segment<3>(3 * t[0]), x.segment<3>(3 * t[1]), x.segment<3>(3 * t[2]), x.segment<3>(3 * t[3])};
}

Eigen::Matrix3d skew(const Eigen::Vector3d& w) {
  Eigen::Matrix3d m;
  m << 0.0, -w.z(), w.y(), w.z(), 0.0, -w.x(), -w.y(), w.x(), 0.0;
  return m;
}

// Elastic forces and, optionally, the sum of squared element force norms (round-off scale).
Eigen::VectorXd assemble_elastic_forces(const Model& model, const Eigen::VectorXd& x, double* element_norm2) {
  const double mu = model.material.lame_mu(), lambda = model.material.lame_lambda();
  Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
  double n2 = 0.0;
  for (int e = 0; e < static_cast<int>(model.mesh.tets.size()); ++e) {
    const TetRest& rest = model.rest[static_cast<std::size_t>(e)];
    const Eigen::Matrix3d F = deformation_gradient(rest, element_positions(model, e, x));
    const Eigen::Matrix3d R = polar_rotation_svd(F);
    const Vec12 fe = corotated_force(rest, F, R, mu, lambda);
    n2 += fe.squaredNorm();
    const Tet& t = model.mesh.tets[static_cast<std::size_t>(e)];
    for (int a = 0; a < 4; ++a) f.segment<3>(3 * t[a]) += fe.segment<3>(3 * a);
  }
  if (element_norm2 != nullptr) *element_norm2 = n2;
  return f;
}

Eigen::VectorXd external_forces(const Model& model, const StaticLoads& loads, const Eigen::VectorXd& x) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
  if (loads.dead.size() == x.size()) f += loads.dead;
  if (loads.gravity.squaredNorm() > 0.0)
    for (int i = 0; i < model.node_count(); ++i) f.segment<3>(3 * i) += model.lumped_mass[i] * loads.gravity;
  if (!loads.chamber_pressures_Pa.empty()) add_pressure_forces(model.mesh, x, loads.chamber_pressures_Pa, f);
  return f;
}

double free_norm(const Eigen::VectorXd& v, const std::vector<bool>& fixed) {
  double s = 0.0;
  for (Eigen::Index i = 0; i < v.size(); ++i)
    if (!fixed[static_cast<std::size_t>(i)]) s += v[i] * v[i];
  return std::sqrt(s);
}

}  // namespace

Eigen::VectorXd elastic_forces(const Model& model, const Eigen::VectorXd& x) {
  return assemble_elastic_forces(model, x, nullptr);
}

double elastic_energy(const Model& model, const Eigen::VectorXd& x) {
  const double mu = model.material.lame_mu(), lambda = model.material.lame_lambda();
  double w = 0.0;
  for (int e = 0; e < static_cast<int>(model.mesh.tets.size()); ++e) {
    const TetRest& rest = model.rest[static_cast<std::size_t>(e)];
    const Eigen::Matrix3d F = deformation_gradient(rest, element_positions(model, e, x));
    w += corotated_energy(rest, F, polar_rotation_svd(F), mu, lambda);
  }
  return w;
}

Mat12 element_tangent(const Model& model, int e, const Eigen::VectorXd& x, StaticTangent kind) {
  const TetRest& rest = model.rest[static_cast<std::size_t>(e)];
  const Eigen::Matrix3d F = deformation_gradient(rest, element_positions(model, e, x));
  const Eigen::Matrix3d R = polar_rotation_svd(F);
  const double mu = model.material.lame_mu(), lambda = model.material.lame_lambda();
  if (kind == StaticTangent::Corotational) return corotated_stiffness(rest_stiffness(rest, mu, lambda), R);

  Eigen::Matrix3d S = R.transpose() * F;
  S = 0.5 * (S + S.transpose()).eval();
  const double tr_strain = S.trace() - 3.0;
  const Eigen::Matrix3d G = (S.trace() * Eigen::Matrix3d::Identity() - S).inverse();
  Mat12 k;
  for (int b = 0; b < 4; ++b)
    for (int c = 0; c < 3; ++c) {
      // dF for a unit displacement of node b along c.
      const Eigen::Matrix3d dF = Eigen::Vector3d::Unit(c) * rest.grad.row(b);
      const Eigen::Matrix3d RtdF = R.transpose() * dF;
      const Eigen::Matrix3d A = RtdF - RtdF.transpose();
      const Eigen::Vector3d w = G * Eigen::Vector3d(A(2, 1), A(0, 2), A(1, 0));
      const Eigen::Matrix3d dR = R * skew(w);
      const Eigen::Matrix3d dP = 2.0 * mu * (dF - dR) + lambda * RtdF.trace() * R + lambda * tr_strain * dR;
      for (int a = 0; a < 4; ++a)
        k.block<3, 1>(3 * a, 3 * b + c) = rest.volume * dP * rest.grad.row(a).transpose();
    }
  return 0.5 * (k + k.transpose());
}

SpMat tangent_stiffness(const Model& model, const Eigen::VectorXd& x, StaticTangent kind) {
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(model.mesh.tets.size() * 144);
  for (int e = 0; e < static_cast<int>(model.mesh.tets.size()); ++e) {
    const Mat12 k = element_tangent(model, e, x, kind);
    const Tet& t = model.mesh.tets[static_cast<std::size_t>(e)];
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b)
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) trip.emplace_back(3 * t[a] + i, 3 * t[b] + j, k(3 * a + i, 3 * b + j));
  }
  SpMat K(x.size(), x.size());
  K.setFromTriplets(trip.begin(), trip.end());
  return K;
}

SpMat lumped_mass_matrix(const Model& model) {
  const int n = model.node_count();
  SpMat M(3 * n, 3 * n);
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(static_cast<std::size_t>(3 * n));
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) trip.emplace_back(3 * i + c, 3 * i + c, model.lumped_mass[i]);
  M.setFromTriplets(trip.begin(), trip.end());
  return M;
}

std::vector<bool> clamped_base_dofs(const Model& model) {
  std::vector<bool> fixed(static_cast<std::size_t>(3 * model.node_count()), false);
  for (int b : model.base_nodes)
    for (int c = 0; c < 3; ++c) fixed[static_cast<std::size_t>(3 * b + c)] = true;
  return fixed;
}

StaticResult solve_static(const Model& model, const StaticLoads& loads, const std::vector<bool>& fixed,
                          const StaticOptions& options, const Eigen::VectorXd& x0) {
  const Eigen::Index n = 3 * static_cast<Eigen::Index>(model.node_count());
  if (static_cast<Eigen::Index>(fixed.size()) != n) throw std::invalid_argument("solve_static: fixed must have 3N flags");
  if (x0.size() != 0 && x0.size() != n) throw std::invalid_argument("solve_static: x0 must be empty or 3N");
  if (loads.dead.size() != 0 && loads.dead.size() != n) throw std::invalid_argument("solve_static: dead load must be 3N");
  if (options.load_steps < 1) throw std::invalid_argument("solve_static: load_steps must be >= 1");

  std::vector<int> map(static_cast<std::size_t>(n), -1);
  std::vector<int> free_dofs;
  for (Eigen::Index i = 0; i < n; ++i)
    if (!fixed[static_cast<std::size_t>(i)]) {
      map[static_cast<std::size_t>(i)] = static_cast<int>(free_dofs.size());
      free_dofs.push_back(static_cast<int>(i));
    }
  const int nf = static_cast<int>(free_dofs.size());

  StaticResult res;
  res.positions = x0.size() == n ? x0 : model.rest_positions;
  Eigen::VectorXd& x = res.positions;
  const Eigen::VectorXd x_start = x;

  // Round-off floor of the residual: a relative error ~64 ε_mach in the strain of every element
  // gives nodal force errors ~64 ε E V ‖∇N‖ that add up randomly.
  double floor2 = 0.0;
  for (const TetRest& rest : model.rest) floor2 += std::pow(rest.volume * rest.grad.norm(), 2);
  const double residual_floor =
      64.0 * std::numeric_limits<double>::epsilon() * model.material.youngs_modulus_Pa * std::sqrt(floor2);
  const auto residual = [&](const Eigen::VectorXd& xs, double load_factor, double* scale) {
    double en2 = 0.0;
    const Eigen::VectorXd fext = load_factor * external_forces(model, loads, xs);
    Eigen::VectorXd r = assemble_elastic_forces(model, xs, &en2) + fext;
    if (scale != nullptr) {
      const double fe = free_norm(fext, fixed);
      *scale = fe > 0.0 ? fe : std::sqrt(en2);
    }
    return r;
  };
  const auto restrict = [&](const Eigen::VectorXd& v) {
    Eigen::VectorXd out(nf);
    for (int i = 0; i < nf; ++i) out[i] = v[free_dofs[static_cast<std::size_t>(i)]];
    return out;
  };
  const auto reduced_matrix = [&](const SpMat& K) {
    std::vector<Eigen::Triplet<double>> trip;
    trip.reserve(static_cast<std::size_t>(K.nonZeros()));
    for (int col = 0; col < K.outerSize(); ++col) {
      const int jc = map[static_cast<std::size_t>(col)];
      if (jc < 0) continue;
      for (SpMat::InnerIterator it(K, col); it; ++it) {
        const int ir = map[static_cast<std::size_t>(it.row())];
        if (ir >= 0) trip.emplace_back(ir, jc, it.value());
      }
      if (options.mass_shift != 0.0)
        trip.emplace_back(jc, jc, options.mass_shift * model.lumped_mass[col / 3]);
    }
    SpMat Kf(nf, nf);
    Kf.setFromTriplets(trip.begin(), trip.end());
    return Kf;
  };

  Eigen::CholmodSupernodalLLT<SpMat, Eigen::Lower> llt;
  bool analysed = false;
  const auto factorise = [&](const SpMat& Kf) {
    if (!analysed) {
      llt.analyzePattern(Kf);
      analysed = true;
    }
    llt.factorize(Kf);
    return llt.info() == Eigen::Success;
  };

  res.load_norm = free_norm(external_forces(model, loads, x), fixed);
  double last_factor = 0.0;
  Eigen::VectorXd x_prev = x;  // equilibrium of the previous load step (predictor)
  for (int step = 1; step <= options.load_steps; ++step) {
    const double lf = static_cast<double>(step) / options.load_steps;
    last_factor = lf;
    if (step >= 2) {
      // Secant predictor: extrapolate the last equal load increment (fixed DOFs do not move).
      const Eigen::VectorXd x_eq = x;
      x += x - x_prev;
      x_prev = x_eq;
    }
    bool step_converged = false;
    for (int it = 0; it <= options.max_iterations; ++it) {
      double scale = 0.0;
      const Eigen::VectorXd r = residual(x, lf, &scale);
      const double rn = free_norm(r, fixed);
      res.residual_norm = rn;
      if (rn <= options.rel_tolerance * scale + options.abs_tolerance_uN + residual_floor) {
        step_converged = true;
        break;
      }
      if (it == options.max_iterations) break;
      ++res.iterations;
      bool ok = factorise(reduced_matrix(tangent_stiffness(model, x, options.tangent)));
      if (!ok && options.tangent == StaticTangent::Consistent) {
        ++res.fallbacks;
        ok = factorise(reduced_matrix(tangent_stiffness(model, x, StaticTangent::Corotational)));
      }
      if (!ok) throw std::runtime_error("solve_static: tangent factorisation failed");
      const Eigen::VectorXd du_f = llt.solve(restrict(r));
      Eigen::VectorXd du = Eigen::VectorXd::Zero(n);
      for (int i = 0; i < nf; ++i) du[free_dofs[static_cast<std::size_t>(i)]] = du_f[i];
      // Line search on the directional residual s(α) = du·r(x + α du) (Crisfield): for a
      // conservative load s = −dΠ/dα, so a root of s is the energy minimum along du. Accept the
      // full step unless |s(1)| > 0.8 |s(0)|; otherwise interpolate linearly (regula falsi).
      double alpha = 1.0;
      if (options.line_search) {
        const double s0 = du.dot(r);
        double a_lo = 0.0, s_lo = s0;
        for (int ls = 0; ls < 6; ++ls) {
          const double s1 = du.dot(residual(x + alpha * du, lf, nullptr));
          if (std::abs(s1) <= 0.8 * std::abs(s0)) break;
          if (s1 * s_lo < 0.0) {
            alpha = a_lo + (alpha - a_lo) * s_lo / (s_lo - s1);  // root between a_lo and alpha
          } else {
            a_lo = alpha;
            s_lo = s1;
            alpha = std::min(4.0, 2.0 * alpha);  // still going downhill: extend
          }
          alpha = std::clamp(alpha, 0.05, 4.0);
        }
      }
      x += alpha * du;
      // Increment criterion: a Newton correction below rel_tolerance of the displacement made by
      // this solve means the residual sits at its round-off floor.
      const double disp = (x - x_start).lpNorm<Eigen::Infinity>();
      if (alpha * du.lpNorm<Eigen::Infinity>() <= options.rel_tolerance * disp) {
        res.residual_norm = free_norm(residual(x, lf, nullptr), fixed);
        step_converged = true;
        break;
      }
    }
    if (!step_converged) {
      res.converged = false;
      break;
    }
    res.converged = true;
  }
  const Eigen::VectorXd r = residual(x, last_factor, nullptr);
  res.reaction = Eigen::VectorXd::Zero(n);
  for (Eigen::Index i = 0; i < n; ++i)
    if (fixed[static_cast<std::size_t>(i)]) res.reaction[i] = -r[i];
  return res;
}

}  // namespace codesign::fem
