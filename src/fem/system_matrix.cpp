#include "fem/system_matrix.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <set>

namespace codesign::fem {

namespace {

std::vector<int> fibre_nodes(const Model& m, const FibreSpring& s) {
  std::vector<int> v;
  for (int a = 0; a < 4; ++a) v.push_back(m.mesh.tets[s.a.tet][a]);
  for (int a = 0; a < 4; ++a) v.push_back(m.mesh.tets[s.b.tet][a]);
  return v;
}

}  // namespace

SystemMatrix::SystemMatrix(const Model& model, const std::vector<int>& free_index) {
  free_nodes_ = 0;
  for (int f : free_index) free_nodes_ += f >= 0;
  std::vector<std::set<int>> lower(free_nodes_);
  auto couple = [&](const int* nodes, int k) {
    for (int a = 0; a < k; ++a)
      for (int b = 0; b < k; ++b) {
        const int fa = free_index[nodes[a]], fb = free_index[nodes[b]];
        if (fa >= 0 && fb >= 0 && fa < fb) lower[fb].insert(fa);
      }
  };
  for (const Tet& t : model.mesh.tets) couple(t.data(), 4);
  for (const FibreSpring& s : model.fibres) {
    const std::vector<int> v = fibre_nodes(model, s);
    couple(v.data(), 8);
  }
  lower_.resize(free_nodes_);
  colptr_.assign(3 * free_nodes_ + 1, 0);
  for (int j = 0; j < free_nodes_; ++j) {
    lower_[j].assign(lower[j].begin(), lower[j].end());
    const int nl = static_cast<int>(lower_[j].size());
    for (int c = 0; c < 3; ++c) colptr_[3 * j + c + 1] = colptr_[3 * j + c] + 3 * nl + c + 1;
  }
  rowind_.resize(colptr_.back());
  for (int j = 0; j < free_nodes_; ++j)
    for (int c = 0; c < 3; ++c) {
      int p = colptr_[3 * j + c];
      for (int i : lower_[j])
        for (int r = 0; r < 3; ++r) rowind_[p++] = 3 * i + r;
      for (int r = 0; r <= c; ++r) rowind_[p++] = 3 * j + r;
    }
  values_.assign(rowind_.size(), 0.0);
}

void SystemMatrix::clear() { std::fill(values_.begin(), values_.end(), 0.0); }

int SystemMatrix::slot(int fi, int fj) const {
  const auto& l = lower_[fj];
  return static_cast<int>(std::lower_bound(l.begin(), l.end(), fi) - l.begin());
}

void SystemMatrix::add_block(int fi, int fj, const Eigen::Matrix3d& B) {
  if (fi == fj) {
    const int nl = static_cast<int>(lower_[fj].size());
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r <= c; ++r) values_[colptr_[3 * fj + c] + 3 * nl + r] += B(r, c);
    return;
  }
  if (fi > fj) {
    add_block(fj, fi, B.transpose());
    return;
  }
  const int k = slot(fi, fj);
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) values_[colptr_[3 * fj + c] + 3 * k + r] += B(r, c);
}

void SystemMatrix::add_diagonal(int fi, double d) {
  const int nl = static_cast<int>(lower_[fi].size());
  for (int c = 0; c < 3; ++c) values_[colptr_[3 * fi + c] + 3 * nl + c] += d;
}

Eigen::Vector3d fibre_force(const Model& model, const FibreSpring& s, const Eigen::VectorXd& x) {
  const Eigen::Vector3d d = embedded_position(model.mesh, s.a, x) - embedded_position(model.mesh, s.b, x);
  const double len = d.norm();
  if (!(len > 0.0) || (model.fibres_tension_only && !(len > s.rest_length_mm))) return Eigen::Vector3d::Zero();
  return -s.stiffness_uN_per_mm * (len - s.rest_length_mm) * (d / len);
}

Eigen::Matrix3d fibre_tangent(const Model& model, const FibreSpring& s, const Eigen::VectorXd& x) {
  const Eigen::Vector3d d = embedded_position(model.mesh, s.a, x) - embedded_position(model.mesh, s.b, x);
  const double len = d.norm();
  if (!(len > 0.0) || (model.fibres_tension_only && !(len > s.rest_length_mm))) return Eigen::Matrix3d::Zero();
  const Eigen::Vector3d n = d / len;
  const Eigen::Matrix3d nn = n * n.transpose();
  const double geo = std::max(0.0, 1.0 - s.rest_length_mm / len);
  return s.stiffness_uN_per_mm * (nn + geo * (Eigen::Matrix3d::Identity() - nn));
}

void assemble_system(const Model& model, const std::vector<int>& free_index,
                     const std::vector<Eigen::Matrix3d>& rotations, const Eigen::VectorXd& x,
                     double c_m, double c_k, SystemMatrix& a) {
  a.clear();
  const int n = model.node_count();
  for (int i = 0; i < n; ++i)
    if (free_index[i] >= 0) a.add_diagonal(free_index[i], c_m * model.lumped_mass[i]);
  const double mu = model.material.lame_mu(), lambda = model.material.lame_lambda();
  for (std::size_t e = 0; e < model.mesh.tets.size(); ++e) {
    const Tet& t = model.mesh.tets[e];
    const Eigen::Matrix3d& R = rotations[e];
    const Mat12 k0 = rest_stiffness(model.rest[e], mu, lambda);
    for (int p = 0; p < 4; ++p) {
      const int fp = free_index[t[p]];
      if (fp < 0) continue;
      for (int q = p; q < 4; ++q) {
        const int fq = free_index[t[q]];
        if (fq < 0) continue;
        const Eigen::Matrix3d B = c_k * (R * k0.block<3, 3>(3 * p, 3 * q) * R.transpose());
        if (p == q) a.add_block(fp, fp, B);
        else a.add_block(fp, fq, B);  // stores B at (fp, fq) and implies Bᵀ at (fq, fp)
      }
    }
  }
  for (const FibreSpring& s : model.fibres) {
    const Eigen::Matrix3d kt = fibre_tangent(model, s, x);
    if (kt.isZero(0.0)) continue;
    int nodes[8];
    double w[8];
    for (int q = 0; q < 4; ++q) {
      nodes[q] = model.mesh.tets[s.a.tet][q], w[q] = s.a.weights[q];
      nodes[4 + q] = model.mesh.tets[s.b.tet][q], w[4 + q] = -s.b.weights[q];
    }
    for (int p = 0; p < 8; ++p) {
      const int fp = free_index[nodes[p]];
      if (fp < 0) continue;
      for (int q = 0; q < 8; ++q) {
        const int fq = free_index[nodes[q]];
        if (fq < 0) continue;
        // Add each ordered pair's share once into the upper triangle: pairs with fp < fq carry
        // the (p, q) block; fp == fq blocks (possibly several per node) add symmetric parts.
        if (fp < fq) a.add_block(fp, fq, c_k * w[p] * w[q] * kt);
        else if (fp == fq) a.add_block(fp, fp, c_k * w[p] * w[q] * kt);
      }
    }
  }
}

}  // namespace codesign::fem
