#include "fem/corotational_tet.hpp"

#include <cmath>
#include <stdexcept>

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

Eigen::Matrix3d polar_rotation(const Eigen::Matrix3d& F, const Eigen::Matrix3d& guess) {
  // Maximise tr(Rᵀ F) over rotations: at the optimum Σ_i r_i × f_i = 0 (r_i, f_i columns).
  // Each iteration turns R about ω = Σ r_i × f_i / (|Σ r_i·f_i| + ε) (Müller et al. 2016).
  Eigen::Quaterniond q(guess);
  q.normalize();
  for (int it = 0; it < 40; ++it) {
    const Eigen::Matrix3d R = q.toRotationMatrix();
    const Eigen::Vector3d num = R.col(0).cross(F.col(0)) + R.col(1).cross(F.col(1)) + R.col(2).cross(F.col(2));
    const double den = std::abs(R.col(0).dot(F.col(0)) + R.col(1).dot(F.col(1)) + R.col(2).dot(F.col(2))) + 1e-300;
    const Eigen::Vector3d w = num / den;
    const double angle = w.norm();
    if (!(angle > 1e-13)) break;  // also stops on NaN
    q = Eigen::Quaterniond(Eigen::AngleAxisd(angle, w / angle)) * q;
    q.normalize();
  }
  return q.toRotationMatrix();
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
