#include "fem/simulator_impl.hpp"



namespace codesign::fem {

bool Simulator::Impl::build_exact(double dt) {
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

bool Simulator::Impl::build_reference(Reference& ref, double dt) {
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

void Simulator::Impl::update_node_rotations() {
  if (static_cast<int>(node_qrot.size()) != nfree) node_qrot.assign(nfree, Eigen::Quaterniond(base_rotation(0.0)));
  const auto& tets = model->mesh.tets;
  if (rotation_terms.size() != tets.size()) {
    rotation_terms.resize(tets.size());
    for (std::size_t e = 0; e < tets.size(); ++e) {
      for (int a = 0; a < 4; ++a) rotation_terms[e].free[a] = free_index[tets[e][a]];
      rotation_terms[e].volume = model->rest[e].volume;
    }
  }
  rotation_acc.assign(nfree, Eigen::Vector4d::Zero());
  for (std::size_t e = 0; e < tets.size(); ++e) {
    const RotationTerm& term = rotation_terms[e];
    const Eigen::Vector4d qe = batch.quaternion(static_cast<int>(e)).coeffs() * term.volume;
    for (int a = 0; a < 4; ++a)
      if (const int k = term.free[a]; k >= 0)
        rotation_acc[k] += qe.dot(node_qrot[k].coeffs()) >= 0.0 ? qe : Eigen::Vector4d(-qe);
  }
  node_rot.resize(nfree);
  for (int k = 0; k < nfree; ++k) {
    const double nrm = rotation_acc[k].norm();
    if (nrm > 0.0) node_qrot[k].coeffs() = rotation_acc[k] / nrm;
    node_rot[k] = node_qrot[k].toRotationMatrix();
  }
}

void Simulator::Impl::update_warp(const Reference& ref) {
  warp.resize(nfree);
  for (int k = 0; k < nfree; ++k) warp[k] = node_rot[k] * ref.node_rot[k].transpose();
}

bool Simulator::Impl::ensure_columns(Reference& ref, int c) {
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

void Simulator::Impl::apply_ref_inverse(Reference& ref, const Eigen::VectorXd& r, Eigen::VectorXd& y) {
  work_u.resize(r.size());
  for (int k = 0; k < nfree; ++k) work_u.segment<3>(3 * k) = warp[k].transpose() * r.segment<3>(3 * k);
  y.resize(r.size());
  ref.factor.solve(work_u.data(), y.data());
  for (int k = 0; k < nfree; ++k) y.segment<3>(3 * k) = warp[k] * y.segment<3>(3 * k).eval();
}

}  // namespace codesign::fem
