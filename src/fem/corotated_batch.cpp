#include "fem/corotated_batch.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>

namespace codesign::fem {

namespace {
constexpr int W = CorotatedBatch::kLanes;
}

CorotatedBatch::CorotatedBatch(const std::vector<Tet>& tets, const std::vector<TetRest>& rest, double mu,
                               double lambda)
    : elements_(static_cast<int>(tets.size())), mu_(mu), lambda_(lambda) {
  if (rest.size() != tets.size()) throw std::invalid_argument("CorotatedBatch: one rest state per element");
  groups_ = (elements_ + W - 1) / W;
  dof_.assign(static_cast<std::size_t>(groups_) * 4 * W, 0);
  grad_.assign(static_cast<std::size_t>(groups_) * 9 * W, 0.0);
  vol_.assign(static_cast<std::size_t>(groups_) * W, 0.0);
  rot_.q.assign(static_cast<std::size_t>(groups_) * 4 * W, 0.0);
  rot_.R.assign(static_cast<std::size_t>(groups_) * 9 * W, 0.0);
  set_all_rotations(Eigen::Matrix3d::Identity());  // until set; padding lanes stay identity
  for (int e = 0; e < elements_; ++e) {
    const std::size_t b = e / W, l = e % W;
    for (int a = 0; a < 4; ++a) dof_[(b * 4 + a) * W + l] = 3 * tets[e][a];
    for (int a = 1; a < 4; ++a)
      for (int j = 0; j < 3; ++j) grad_[(b * 9 + 3 * (a - 1) + j) * W + l] = rest[e].grad(a, j);
    vol_[b * W + l] = rest[e].volume;
  }
}

namespace {

// dF = Σ_a u_a ∇N_aᵀ = Σ_{a≥1} (u_a − u_0) ∇N_aᵀ (∇N_0 = −Σ_{a≥1} ∇N_a), for lane l.
[[gnu::always_inline]] inline void gradient_lane(const double* uu, const int* dof, const double* g, int l,
                                                 double dF[3][3]) {
  double du[3][3];
  for (int a = 1; a < 4; ++a)
    for (int i = 0; i < 3; ++i) du[a - 1][i] = uu[dof[a * W + l] + i] - uu[dof[l] + i];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      dF[i][j] = du[0][i] * g[(0 + j) * W + l] + du[1][i] * g[(3 + j) * W + l] + du[2][i] * g[(6 + j) * W + l];
}

// Nodal vectors y_a = c R σ(ε) ∇N_a of lane l, with ε = sym(Rᵀ G) − shift·I and
// σ = 2μ ε + λ tr(ε) I; y_0 = −Σ_{a≥1} y_a. Into out[3a + i][l].
[[gnu::always_inline]] inline void stress_lane(const double* R, const double* g, int l, const double G[3][3],
                                               double shift, double c, double two_mu, double lambda,
                                               double out[12][W]) {
  double L[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      L[i][j] = R[(0 + i) * W + l] * G[0][j] + R[(3 + i) * W + l] * G[1][j] + R[(6 + i) * W + l] * G[2][j];
  double s[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) s[i][j] = 0.5 * two_mu * (L[i][j] + L[j][i]);
  const double tr = lambda * (L[0][0] + L[1][1] + L[2][2] - 3.0 * shift);
  for (int i = 0; i < 3; ++i) s[i][i] += tr - two_mu * shift;
  double P[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      P[i][j] = c * (R[(3 * i + 0) * W + l] * s[0][j] + R[(3 * i + 1) * W + l] * s[1][j] +
                     R[(3 * i + 2) * W + l] * s[2][j]);
  for (int i = 0; i < 3; ++i) {
    double sum = 0.0;
    for (int a = 1; a < 4; ++a) {
      const double v = P[i][0] * g[(3 * (a - 1) + 0) * W + l] + P[i][1] * g[(3 * (a - 1) + 1) * W + l] +
                       P[i][2] * g[(3 * (a - 1) + 2) * W + l];
      out[3 * a + i][l] = v;
      sum += v;
    }
    out[i][l] = -sum;
  }
}

void scatter(const int* dof, int lanes, const double out[12][W], double* yy) {
  for (int l = 0; l < lanes; ++l)
    for (int a = 0; a < 4; ++a) {
      double* yn = yy + dof[a * W + l];
      yn[0] += out[3 * a + 0][l];
      yn[1] += out[3 * a + 1][l];
      yn[2] += out[3 * a + 2][l];
    }
}

// Rotation matrix of the unit quaternion (w, x, y, z) (as Eigen's toRotationMatrix).
[[gnu::always_inline]] inline void quat_to_matrix(double w, double x, double y, double z, double* R, int l) {
  R[0 * W + l] = 1.0 - 2.0 * (y * y + z * z);
  R[1 * W + l] = 2.0 * (x * y - z * w);
  R[2 * W + l] = 2.0 * (x * z + y * w);
  R[3 * W + l] = 2.0 * (x * y + z * w);
  R[4 * W + l] = 1.0 - 2.0 * (x * x + z * z);
  R[5 * W + l] = 2.0 * (y * z - x * w);
  R[6 * W + l] = 2.0 * (x * z - y * w);
  R[7 * W + l] = 2.0 * (y * z + x * w);
  R[8 * W + l] = 1.0 - 2.0 * (x * x + y * y);
}

// polar_rotation() for the W lanes of one group at once: F[9][W] (row-major 3×3 per lane),
// q[4][W] (w, x, y, z) in and out, R[9][W] out. The same iteration and stopping rules; the
// rotation increment's cos and sin come from their series to h⁸ (error < 3e-13 for a turn
// below half a radian) and from std::cos/sin above that, in a scalar fix-up.
void polar_lanes(const double F[9][W], double q[4][W], double* R, int lanes, double tol) {
  const double tol2 = tol * tol;
  bool active[W];
  for (int l = 0; l < W; ++l) {
    const double n = std::sqrt(q[0][l] * q[0][l] + q[1][l] * q[1][l] + q[2][l] * q[2][l] + q[3][l] * q[3][l]);
    for (int k = 0; k < 4; ++k) q[k][l] /= n;
    quat_to_matrix(q[0][l], q[1][l], q[2][l], q[3][l], R, l);
    active[l] = l < lanes;
  }
  for (int it = 0; it < 60; ++it) {
    bool any = false;
    for (int l = 0; l < W; ++l) any |= active[l];
    if (!any) break;
    double wv[3][W], ang2[W], qp[4][W];
    bool big[W];
    for (int l = 0; l < W; ++l) {
      double A[3][3];  // Rᵀ F
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          A[i][j] = R[(0 + i) * W + l] * F[0 + j][l] + R[(3 + i) * W + l] * F[3 + j][l] + R[(6 + i) * W + l] * F[6 + j][l];
      const double a0 = 0.5 * (A[2][1] - A[1][2]), a1 = 0.5 * (A[0][2] - A[2][0]), a2 = 0.5 * (A[1][0] - A[0][1]);
      const double tr = A[0][0] + A[1][1] + A[2][2];
      const double m00 = tr - A[0][0], m11 = tr - A[1][1], m22 = tr - A[2][2];
      const double m01 = -0.5 * (A[0][1] + A[1][0]), m02 = -0.5 * (A[0][2] + A[2][0]), m12 = -0.5 * (A[1][2] + A[2][1]);
      const double c00 = m11 * m22 - m12 * m12, c01 = m02 * m12 - m01 * m22, c02 = m01 * m12 - m02 * m11;
      const double det = m00 * c00 + m01 * c01 + m02 * c02;
      const double minor2 = m00 * m11 - m01 * m01;
      const bool newton = m00 > 0.0 && minor2 > 0.0 && det > 0.0;
      const double c11 = m00 * m22 - m02 * m02, c12 = m02 * m01 - m00 * m12, c22 = minor2;
      const double s2 = 2.0 / (newton ? det : 1.0);
      const double sf = 2.0 / (std::abs(tr) + 1e-300);
      const double w0 = newton ? s2 * (c00 * a0 + c01 * a1 + c02 * a2) : sf * a0;
      const double w1 = newton ? s2 * (c01 * a0 + c11 * a1 + c12 * a2) : sf * a1;
      const double w2 = newton ? s2 * (c02 * a0 + c12 * a1 + c22 * a2) : sf * a2;
      const double angle2 = w0 * w0 + w1 * w1 + w2 * w2;
      const bool step = active[l] && angle2 > 1e-30;  // also false on NaN
      // cos(|w|/2) and sin(|w|/2)/|w| by their series in h² = |w|²/4.
      const double h2 = 0.25 * angle2;
      const double cw = 1.0 - h2 * (1.0 / 2 - h2 * (1.0 / 24 - h2 * (1.0 / 720 - h2 * (1.0 / 40320))));
      const double sw = 0.5 * (1.0 - h2 * (1.0 / 6 - h2 * (1.0 / 120 - h2 * (1.0 / 5040 - h2 * (1.0 / 362880)))));
      const double dw = step ? cw : 1.0, dx = step ? sw * w0 : 0.0, dy = step ? sw * w1 : 0.0, dz = step ? sw * w2 : 0.0;
      // q ← q dq (the correction is in the element frame), normalised.
      const double qw = q[0][l], qx = q[1][l], qy = q[2][l], qz = q[3][l];
      qp[0][l] = qw, qp[1][l] = qx, qp[2][l] = qy, qp[3][l] = qz;
      double nw = qw * dw - qx * dx - qy * dy - qz * dz;
      double nx = qw * dx + qx * dw + qy * dz - qz * dy;
      double ny = qw * dy - qx * dz + qy * dw + qz * dx;
      double nz = qw * dz + qx * dy - qy * dx + qz * dw;
      const double inv = 1.0 / std::sqrt(nw * nw + nx * nx + ny * ny + nz * nz);
      nw *= inv, nx *= inv, ny *= inv, nz *= inv;
      if (step) {
        q[0][l] = nw, q[1][l] = nx, q[2][l] = ny, q[3][l] = nz;
        quat_to_matrix(nw, nx, ny, nz, R, l);
      }
      wv[0][l] = w0, wv[1][l] = w1, wv[2][l] = w2, ang2[l] = angle2;
      big[l] = step && angle2 >= 0.25;  // |w| ≥ 0.5 rad: the series above is not exact there
      // Newton converges quadratically: after a Newton step of |w| the error is O(|w|²).
      active[l] = step && !((angle2 < tol && newton) || angle2 < tol2);
    }
    for (int l = 0; l < W; ++l) {
      if (!big[l]) continue;
      // Redo this lane's update from the quaternion before it, with exact cos and sin.
      const double angle = std::sqrt(ang2[l]);
      const double dw = std::cos(0.5 * angle), sw = std::sin(0.5 * angle) / angle;
      const double dx = sw * wv[0][l], dy = sw * wv[1][l], dz = sw * wv[2][l];
      const double qw = qp[0][l], qx = qp[1][l], qy = qp[2][l], qz = qp[3][l];
      const Eigen::Quaterniond nq =
          Eigen::Quaterniond(qw * dw - qx * dx - qy * dy - qz * dz, qw * dx + qx * dw + qy * dz - qz * dy,
                             qw * dy - qx * dz + qy * dw + qz * dx, qw * dz + qx * dy - qy * dx + qz * dw)
              .normalized();
      q[0][l] = nq.w(), q[1][l] = nq.x(), q[2][l] = nq.y(), q[3][l] = nq.z();
      quat_to_matrix(nq.w(), nq.x(), nq.y(), nq.z(), R, l);
    }
  }
}

}  // namespace

void CorotatedBatch::set_all_rotations(const Eigen::Matrix3d& G) {
  const Eigen::Quaterniond qg(G);
  const double qv[4] = {qg.w(), qg.x(), qg.y(), qg.z()};
  for (int b = 0; b < groups_; ++b)
    for (int l = 0; l < W; ++l) {
      const bool real = b * W + l < elements_;
      for (int k = 0; k < 4; ++k) rot_.q[(static_cast<std::size_t>(b) * 4 + k) * W + l] = real ? qv[k] : k == 0 ? 1.0 : 0.0;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          rot_.R[(static_cast<std::size_t>(b) * 9 + 3 * i + j) * W + l] = real ? G(i, j) : i == j ? 1.0 : 0.0;
    }
}

void CorotatedBatch::set_all_rotation_matrices(const Eigen::Matrix3d& G) {
  for (int e = 0; e < elements_; ++e) {
    const std::size_t b = e / W, l = e % W;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) rot_.R[(b * 9 + 3 * i + j) * W + l] = G(i, j);
  }
}

Eigen::Matrix3d CorotatedBatch::rotation(int e) const {
  const std::size_t b = e / W, l = e % W;
  Eigen::Matrix3d R;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R(i, j) = rot_.R[(b * 9 + 3 * i + j) * W + l];
  return R;
}

std::vector<Eigen::Matrix3d> CorotatedBatch::rotation_matrices() const {
  std::vector<Eigen::Matrix3d> out(static_cast<std::size_t>(elements_));
  for (int e = 0; e < elements_; ++e) out[static_cast<std::size_t>(e)] = rotation(e);
  return out;
}

void CorotatedBatch::set_rotations(const Rotations& r) {
  if (r.q.size() != rot_.q.size() || r.R.size() != rot_.R.size())
    throw std::invalid_argument("CorotatedBatch::set_rotations: rotations of another mesh");
  rot_ = r;
}

void CorotatedBatch::add_stiffness_times(const Eigen::VectorXd& u, Eigen::VectorXd& y) const {
  const double* uu = u.data();
  double* yy = y.data();
  for (int b = 0; b < groups_; ++b) {
    const int* dof = &dof_[static_cast<std::size_t>(b) * 4 * W];
    const double* g = &grad_[static_cast<std::size_t>(b) * 9 * W];
    const double* R = &rot_.R[static_cast<std::size_t>(b) * 9 * W];
    const double* vol = &vol_[static_cast<std::size_t>(b) * W];
    double out[12][W];
    for (int l = 0; l < W; ++l) {
      double dF[3][3];
      gradient_lane(uu, dof, g, l, dF);
      stress_lane(R, g, l, dF, 0.0, vol[l], 2.0 * mu_, lambda_, out);
    }
    scatter(dof, std::min(W, elements_ - b * W), out, yy);
  }
}

int CorotatedBatch::elastic_pass(const Eigen::VectorXd& x, double tolerance, Eigen::VectorXd& f,
                                 const Eigen::VectorXd* u, Eigen::VectorXd* ku, double* bad_det) {
  const double* xx = x.data();
  const double two_mu = 2.0 * mu_;
  for (int b = 0; b < groups_; ++b) {
    const int* dof = &dof_[static_cast<std::size_t>(b) * 4 * W];
    const double* g = &grad_[static_cast<std::size_t>(b) * 9 * W];
    double* R = &rot_.R[static_cast<std::size_t>(b) * 9 * W];
    double* qb = &rot_.q[static_cast<std::size_t>(b) * 4 * W];
    const double* vol = &vol_[static_cast<std::size_t>(b) * W];
    const int e0 = b * W, lanes = std::min(W, elements_ - e0);
    double F[9][W], det[W];
    for (int l = 0; l < W; ++l) {
      double Fl[3][3];
      gradient_lane(xx, dof, g, l, Fl);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) F[3 * i + j][l] = Fl[i][j];
      det[l] = Fl[0][0] * (Fl[1][1] * Fl[2][2] - Fl[1][2] * Fl[2][1]) -
               Fl[0][1] * (Fl[1][0] * Fl[2][2] - Fl[1][2] * Fl[2][0]) +
               Fl[0][2] * (Fl[1][0] * Fl[2][1] - Fl[1][1] * Fl[2][0]);
    }
    for (int l = 0; l < lanes; ++l)
      if (!(det[l] > 0.0)) {
        if (bad_det) *bad_det = det[l];
        return e0 + l;
      }
    double qs[4][W];
    for (int k = 0; k < 4; ++k)
      for (int l = 0; l < W; ++l) qs[k][l] = qb[k * W + l];
    polar_lanes(F, qs, R, lanes, tolerance);
    for (int k = 0; k < 4; ++k)
      for (int l = 0; l < lanes; ++l) qb[k * W + l] = qs[k][l];
    double out[12][W];
    for (int l = 0; l < W; ++l) {
      double Fl[3][3];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) Fl[i][j] = F[3 * i + j][l];
      stress_lane(R, g, l, Fl, 1.0, -vol[l], two_mu, lambda_, out);
    }
    scatter(dof, lanes, out, f.data());
    if (u) {
      for (int l = 0; l < W; ++l) {
        double dF[3][3];
        gradient_lane(u->data(), dof, g, l, dF);
        stress_lane(R, g, l, dF, 0.0, vol[l], two_mu, lambda_, out);
      }
      scatter(dof, lanes, out, ku->data());
    }
  }
  return -1;
}

}  // namespace codesign::fem
