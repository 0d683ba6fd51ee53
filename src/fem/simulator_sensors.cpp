#include "fem/simulator_impl.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "fem/pressure.hpp"

namespace codesign::fem {

Sensors Simulator::sensors() const {
  const Impl& m = *impl_;
  Sensors s;
  s.time_s = m.t;
  s.theta_rad = m.theta;
  double F = 0.0;
  for (const auto& c : m.contacts) F += c.second;
  s.contact_force_mN = 1e-3 * F;
  s.active_contacts = static_cast<int>(m.contacts.size());
  s.in_contact = F > 0.0;
  s.theta_extreme = std::abs(m.theta) > m.scene.theta_limit_deg * std::numbers::pi / 180.0;
  s.plate_z_mm = m.plate_at(m.t);
  const Model& md = *m.model;
  double acc = 0.0;
  for (int e : md.chamber_tets) {
    const Tet& tt = md.mesh.tets[e];
    const std::array<Eigen::Vector3d, 4> xe{m.x.segment<3>(3 * tt[0]), m.x.segment<3>(3 * tt[1]),
                                            m.x.segment<3>(3 * tt[2]), m.x.segment<3>(3 * tt[3])};
    const Eigen::Matrix3d F = deformation_gradient(md.rest[e], xe);
    acc += md.rest[e].volume * (F.col(0).norm() - 1.0);
  }
  s.axial_strain = md.chamber_volume_mm3 > 0.0 ? acc / md.chamber_volume_mm3 : 0.0;
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();
  for (int i : md.tip_nodes) tip += m.x.segment<3>(3 * i);
  s.tip_position_mm = tip / std::max<std::size_t>(1, md.tip_nodes.size());
  return s;
}

std::vector<double> Simulator::element_axial_strain() const {
  const Impl& m = *impl_;
  const Model& md = *m.model;
  std::vector<double> out(md.mesh.tets.size());
  for (std::size_t e = 0; e < out.size(); ++e) {
    const Tet& tt = md.mesh.tets[e];
    const std::array<Eigen::Vector3d, 4> xe{m.x.segment<3>(3 * tt[0]), m.x.segment<3>(3 * tt[1]),
                                            m.x.segment<3>(3 * tt[2]), m.x.segment<3>(3 * tt[3])};
    out[e] = deformation_gradient(md.rest[e], xe).col(0).norm() - 1.0;
  }
  return out;
}

Eigen::Vector3d Simulator::base_reaction() const {
  Impl& m = *impl_;
  Eigen::VectorXd ff;
  std::string why;
  const CorotatedBatch::Rotations keep = m.batch.rotations();
  const std::vector<Eigen::Matrix3d> keepk = m.fibre_kt;
  m.force_pass(m.x, ff, why);  // the caches (rotations, fibre tangents) stay those of the step
  m.batch.set_rotations(keep);
  m.fibre_kt = keepk;
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  for (int b : m.model->base_nodes) r -= ff.segment<3>(3 * b);
  return r;
}

Eigen::Vector3d Simulator::pressure_force() const {
  const Impl& m = *impl_;
  Eigen::VectorXd ff = Eigen::VectorXd::Zero(3 * m.n);
  add_pressure_forces(m.model->mesh, m.x, m.pressures_Pa, ff);
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  for (int i = 0; i < m.n; ++i) s += ff.segment<3>(3 * i);
  return s;
}

}  // namespace codesign::fem
