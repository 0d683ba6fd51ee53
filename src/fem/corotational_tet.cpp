#include "fem/corotational_tet.hpp"

#include <cmath>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <Eigen/SVD>

namespace codesign::fem {

TetRest make_tet_rest(const std::array<Eigen::Vector3d, 4>& X) {
  Eigen::Matrix3d dm;
  dm << X[1] - X[0], X[2] - X[0], X[3] - X[0];
  const double det = dm.determinant();
  const double scale = std::max({(X[1] - X[0]).norm(), (X[2] - X[0]).norm(), (X[3] - X[0]).norm()});
  if (!(det > 1e-12 * scale * scale * scale))
    throw std::invalid_argument("make_tet_rest: degenerate or negatively oriented tetrahedron");
  TetRest r;
  r.dm_inv = dm.inverse();
  r.volume = det / 6.0;
  // ∇N_a for a = 1..3 are the rows of Dm⁻¹; ∇N_0 = −Σ.
  r.grad.row(1) = r.dm_inv.row(0);
  r.grad.row(2) = r.dm_inv.row(1);
  r.grad.row(3) = r.dm_inv.row(2);
  r.grad.row(0) = -(r.grad.row(1) + r.grad.row(2) + r.grad.row(3));
  return r;
}

Eigen::Matrix3d deformation_gradient(const TetRest& rest, const std::array<Eigen::Vector3d, 4>& x) {
  Eigen::Matrix3d ds;
  ds << x[1] - x[0], x[2] - x[0], x[3] - x[0];
  return ds * rest.dm_inv;
}

Eigen::Quaterniond polar_rotation(const Eigen::Matrix3d& F, const Eigen::Quaterniond& guess, double tolerance,
                                  Eigen::Matrix3d* rotation) {
  // Find R with Rᵀ F symmetric. With A = Rᵀ F, a = axial(skew A) and R ← R exp([ω]×), the
  // linearised condition skew(A) = ½ [(tr A · I − sym A) ω]× gives the Newton step
  //   ω = 2 (tr A · I − sym A)⁻¹ a       (quadratic convergence from a warm start);
  // where that matrix is not positive definite (far from the solution) the step of Müller et
  // al. (2016), ω = 2a / |tr A|, is taken instead (globally robust, linear convergence).
  Eigen::Quaterniond q = guess;
  q.normalize();
  const double tol2 = tolerance * tolerance;
  Eigen::Matrix3d R = q.toRotationMatrix();
  for (int it = 0; it < 60; ++it) {
    const Eigen::Matrix3d A = R.transpose() * F;
    const Eigen::Vector3d a(0.5 * (A(2, 1) - A(1, 2)), 0.5 * (A(0, 2) - A(2, 0)), 0.5 * (A(1, 0) - A(0, 1)));
    const double tr = A.trace();
    const Eigen::Matrix3d M = tr * Eigen::Matrix3d::Identity() - 0.5 * (A + A.transpose());
    // Solve M w = 2a by cofactors (M symmetric); Sylvester's criterion decides definiteness.
    const double c00 = M(1, 1) * M(2, 2) - M(1, 2) * M(1, 2);
    const double c01 = M(0, 2) * M(1, 2) - M(0, 1) * M(2, 2);
    const double c02 = M(0, 1) * M(1, 2) - M(0, 2) * M(1, 1);
    const double det = M(0, 0) * c00 + M(0, 1) * c01 + M(0, 2) * c02;
    const double minor2 = M(0, 0) * M(1, 1) - M(0, 1) * M(0, 1);
    Eigen::Vector3d w;
    const bool newton = M(0, 0) > 0.0 && minor2 > 0.0 && det > 0.0;
    if (newton) {
      const double c11 = M(0, 0) * M(2, 2) - M(0, 2) * M(0, 2);
      const double c12 = M(0, 2) * M(0, 1) - M(0, 0) * M(1, 2);
      const double c22 = minor2;
      const double s2 = 2.0 / det;
      w << s2 * (c00 * a[0] + c01 * a[1] + c02 * a[2]), s2 * (c01 * a[0] + c11 * a[1] + c12 * a[2]),
          s2 * (c02 * a[0] + c12 * a[1] + c22 * a[2]);
    } else {
      w = (2.0 / (std::abs(tr) + 1e-300)) * a;
    }
    const double angle2 = w.squaredNorm();
    if (!(angle2 > 1e-30)) break;  // converged; also stops on NaN
    Eigen::Quaterniond dq;
    if (angle2 < 1e-6) {
      // Small turn: cos(x/2) and sin(x/2)/x by their Taylor series (error < 1e-19).
      dq.w() = 1.0 - angle2 / 8.0;
      dq.vec() = (0.5 - angle2 / 48.0) * w;
    } else {
      const double angle = std::sqrt(angle2);
      dq.w() = std::cos(0.5 * angle);
      dq.vec() = (std::sin(0.5 * angle) / angle) * w;
    }
    q = q * dq;  // R exp([ω]×): the correction is in the element frame
    q.normalize();
    R = q.toRotationMatrix();
    // Newton converges quadratically: after a Newton step of |ω| the remaining error is
    // O(|ω|²), so stop without another pass once |ω|² is below the tolerance.
    if (angle2 < tolerance && newton) break;
    if (angle2 < tol2) break;
  }
  // R is q.toRotationMatrix() of the final q on every path out of the loop.
  if (rotation) *rotation = R;
  return q;
}

Eigen::Matrix3d polar_rotation(const Eigen::Matrix3d& F, const Eigen::Matrix3d& guess) {
  Eigen::Matrix3d R;
  polar_rotation(F, Eigen::Quaterniond(guess), 1e-14, &R);
  return R;
}

Eigen::Matrix3d polar_rotation_svd(const Eigen::Matrix3d& F) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d U = svd.matrixU();
  const Eigen::Matrix3d V = svd.matrixV();
  if ((U * V.transpose()).determinant() < 0.0) U.col(2) *= -1.0;
  return U * V.transpose();
}

Mat12 rest_stiffness(const TetRest& rest, double mu, double lambda) {
  // K0_{ab} = V (μ (∇N_a·∇N_b) I + μ ∇N_b ∇N_aᵀ + λ ∇N_a ∇N_bᵀ)   (3×3 block of nodes a, b)
  Mat12 k;
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b) {
      const Eigen::Vector3d ga = rest.grad.row(a).transpose(), gb = rest.grad.row(b).transpose();
      k.block<3, 3>(3 * a, 3 * b) =
          rest.volume * (mu * ga.dot(gb) * Eigen::Matrix3d::Identity() + mu * gb * ga.transpose() +
                         lambda * ga * gb.transpose());
    }
  return k;
}

namespace {

inline Eigen::Matrix3d stress(const Eigen::Matrix3d& eps, double mu, double lambda) {
  return 2.0 * mu * eps + lambda * eps.trace() * Eigen::Matrix3d::Identity();
}

}  // namespace

double corotated_energy(const TetRest& rest, const Eigen::Matrix3d& F, const Eigen::Matrix3d& R,
                        double mu, double lambda) {
  const Eigen::Matrix3d S = R.transpose() * F;
  const Eigen::Matrix3d eps = 0.5 * (S + S.transpose()) - Eigen::Matrix3d::Identity();
  return rest.volume * (mu * eps.squaredNorm() + 0.5 * lambda * eps.trace() * eps.trace());
}

Vec12 corotated_force(const TetRest& rest, const Eigen::Matrix3d& F, const Eigen::Matrix3d& R,
                      double mu, double lambda) {
  const Eigen::Matrix3d S = R.transpose() * F;
  const Eigen::Matrix3d eps = 0.5 * (S + S.transpose()) - Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d P = R * stress(eps, mu, lambda);
  Vec12 f;
  for (int a = 0; a < 4; ++a) f.segment<3>(3 * a) = -rest.volume * (P * rest.grad.row(a).transpose());
  return f;
}

Mat12 corotated_stiffness(const Mat12& k0, const Eigen::Matrix3d& R) {
  Mat12 k;
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b)
      k.block<3, 3>(3 * a, 3 * b) = R * k0.block<3, 3>(3 * a, 3 * b) * R.transpose();
  return k;
}

Vec12 corotated_stiffness_times(const TetRest& rest, const Eigen::Matrix3d& R, const Vec12& u,
                                double mu, double lambda) {
  Eigen::Matrix3d dF = Eigen::Matrix3d::Zero();
  for (int a = 0; a < 4; ++a) dF.noalias() += u.segment<3>(3 * a) * rest.grad.row(a);
  const Eigen::Matrix3d L = R.transpose() * dF;
  const Eigen::Matrix3d eps = 0.5 * (L + L.transpose());
  const Eigen::Matrix3d P = R * stress(eps, mu, lambda);
  Vec12 y;
  for (int a = 0; a < 4; ++a) y.segment<3>(3 * a) = rest.volume * (P * rest.grad.row(a).transpose());
  return y;
}

}  // namespace codesign::fem
