#include "fem/simulator_impl.hpp"

#include <stdexcept>

namespace codesign::fem {

struct Simulator::Snapshot::Data {
  const Model* model = nullptr;
  Eigen::VectorXd x, v, f, v_prev;
  double omega_last = 0.0;
  CorotatedBatch::Rotations rotations;
  std::vector<Eigen::Matrix3d> fibre_kt;
  double t = 0.0, theta = 0.0, theta_from = 0.0, theta_to = 0.0;
  int ramp_total = 0, ramp_done = 0;
  std::vector<double> pressures_Pa;
  double z_touch = 0.0, z_mean = 0.0, plate_phase_rad = 0.0;
  std::vector<std::pair<int, double>> contacts;
  std::vector<char> was_active;
  std::vector<Eigen::Quaterniond> node_qrot;
  std::vector<Eigen::Matrix3d> node_rot;
  bool dynamic_cur = false;  // the dynamic step had a factor at a deformed state
  // Set when that factor was the one built by settle(): restore() into the same simulator then
  // reuses it while the simulator still holds it (same token).
  std::shared_ptr<const int> settled_token;
};


Simulator::Snapshot Simulator::snapshot() const {
  const Impl& m = *impl_;
  auto d = std::make_shared<Snapshot::Data>();
  d->model = m.model.get();
  d->x = m.x, d->v = m.v, d->f = m.f, d->v_prev = m.v_prev;
  d->omega_last = m.omega_last;
  d->rotations = m.batch.rotations(), d->fibre_kt = m.fibre_kt;
  d->t = m.t, d->theta = m.theta, d->theta_from = m.theta_from, d->theta_to = m.theta_to;
  d->ramp_total = m.ramp_total, d->ramp_done = m.ramp_done;
  d->pressures_Pa = m.pressures_Pa;
  d->z_touch = m.z_touch, d->z_mean = m.z_mean, d->plate_phase_rad = m.scene.plate_phase_rad;
  d->contacts = m.contacts, d->was_active = m.was_active;
  d->node_qrot = m.node_qrot, d->node_rot = m.node_rot;
  d->dynamic_cur = m.slots[0].use != Impl::RefSlot::Use::Rest;
  if (m.slots[0].use == Impl::RefSlot::Use::Settled) d->settled_token = m.settled_token;
  Snapshot s;
  s.data_ = std::move(d);
  return s;
}

StepResult Simulator::restore(const Snapshot& snapshot) {
  if (!snapshot.data_) throw std::invalid_argument("Simulator::restore: empty snapshot");
  const Snapshot::Data& d = *snapshot.data_;
  Impl& m = *impl_;
  if (d.model != m.model.get()) throw std::invalid_argument("Simulator::restore: snapshot of another model");
  m.x = d.x, m.v = d.v, m.f = d.f, m.v_prev = d.v_prev;
  m.omega_last = d.omega_last;
  m.batch.set_rotations(d.rotations);
  m.fibre_kt = d.fibre_kt;
  m.t = d.t, m.theta = d.theta, m.theta_from = d.theta_from, m.theta_to = d.theta_to;
  m.ramp_total = d.ramp_total, m.ramp_done = d.ramp_done;
  m.pressures_Pa = d.pressures_Pa;
  m.z_touch = d.z_touch, m.z_mean = d.z_mean, m.scene.plate_phase_rad = d.plate_phase_rad;
  m.contacts = d.contacts, m.was_active = d.was_active;
  m.node_qrot = d.node_qrot, m.node_rot = d.node_rot;
  m.broken = false;
  for (Impl::RefSlot& sl : m.slots) sl.use = Impl::RefSlot::Use::Rest;
  StepResult r;
  if (m.solver.method == StepMethod::Fast && d.settled_token && d.settled_token == m.settled_token) {
    // The factor settle() built at exactly this state is still here: the same matrix, so the
    // same factor a refactorisation would give (bit-identical), without its cost.
    m.slots[0].use = Impl::RefSlot::Use::Settled;
  } else if (m.solver.method == StepMethod::Fast && d.dynamic_cur) {
    // The factor depends only on x and the element rotations (restored above), as at the end
    // of settle(); the node rotations it stores come from the restored quaternions.
    Impl::RefSlot& sl = m.slot(true);
    if (!m.build_reference(sl.cur, m.solver.dt_s))
      return m.fail(StepStatus::SolverFailure, "CHOLMOD factorisation at the restored state failed");
    sl.use = Impl::RefSlot::Use::Cur;
    r.refactorised = true;
  }
  return r;
}

}  // namespace codesign::fem
