#include "fem/simulator_impl.hpp"

#include <algorithm>
#include <cmath>

#include "fem/pressure.hpp"

namespace codesign::fem {

StepStatus Simulator::Impl::force_pass(const Eigen::VectorXd& xx, Eigen::VectorXd& ff, std::string& why,
                                       const Eigen::VectorXd* u, Eigen::VectorXd* ku,
                                       double rotation_tolerance) {
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

void Simulator::Impl::apply_K(const Eigen::VectorXd& u, Eigen::VectorXd& y) {
  y.setZero(3 * n);
  batch.add_stiffness_times(u, y);
  add_fibre_K(u, y);
}

void Simulator::Impl::add_fibre_K(const Eigen::VectorXd& u, Eigen::VectorXd& y) const {
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

void Simulator::Impl::apply_A(const Eigen::VectorXd& u, double c_m, double c_k, Eigen::VectorXd& y) {
  apply_K(u, y);
  y *= c_k;
  for (int i = 0; i < n; ++i) y.segment<3>(3 * i) += c_m * model->lumped_mass[i] * u.segment<3>(3 * i);
}

double Simulator::Impl::force_scale() const {
  double ff = 0.0, ww = 0.0;
  const double g = model->material.gravity_mm_s2;
  for (int i = 0; i < n; ++i) {
    if (free_index[i] < 0) continue;
    ff += f.segment<3>(3 * i).squaredNorm();
    ww += model->lumped_mass[i] * model->lumped_mass[i] * g * g;
  }
  return std::sqrt(std::max(ff, ww));
}

}  // namespace codesign::fem
