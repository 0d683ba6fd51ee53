#include "fem/simulator_impl.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace codesign::fem {

const char* to_string(StepStatus s) { return name_of(kStepStatusNames, s).data(); }

Simulator::Impl::Impl(std::shared_ptr<const Model> m, const SceneConfig& sc, const SolverConfig& so)
    : model(std::move(m)), scene(sc), solver(so) {
  n = model->node_count();
  free_index.assign(n, -1);
  for (int i = 0; i < n; ++i)
    if (!model->is_base[i]) free_index[i] = nfree++, free_nodes.push_back(i);
  mu = model->material.lame_mu();
  lambda = model->material.lame_lambda();
  A.emplace(*model, free_index);
  batch = CorotatedBatch(model->mesh.tets, model->rest, mu, lambda);
  reset();
}

void Simulator::Impl::reset() {
  const Eigen::Matrix3d G = base_rotation(0.0);
  x.resize(3 * n);
  for (int i = 0; i < n; ++i) x.segment<3>(3 * i) = G * model->rest_positions.segment<3>(3 * i);
  v = Eigen::VectorXd::Zero(3 * n);
  v_prev = v;
  omega_last = 0.0;
  f = Eigen::VectorXd::Zero(3 * n);
  batch.set_all_rotations(G);
  t = 0.0;
  theta = theta_from = theta_to = 0.0;
  ramp_total = ramp_done = 0;
  pressures_Pa = {0.0, 0.0};
  z_touch = 1e300;
  for (int c : model->contact_nodes) z_touch = std::min(z_touch, x[3 * c + 2]);
  if (model->contact_nodes.empty()) z_touch = -1e9;
  z_mean = z_touch + scene.preload_mm;
  contacts.clear();
  was_active.assign(model->contact_nodes.size(), 0);
  broken = false;
  for (RefSlot& sl : slots) sl.use = RefSlot::Use::Rest;
}

StepResult Simulator::Impl::fail(StepStatus s, std::string why) {
  broken = true;
  StepResult r;
  r.status = s;
  r.reason = std::move(why);
  return r;
}

StepResult Simulator::Impl::advance(bool dynamic, std::optional<double> plate_override) {
  if (broken) return fail(StepStatus::SolverFailure, "simulator is in a failed state; call reset()");
  const double dt = dynamic ? solver.dt_s : solver.static_dt_s;
  // Base angle for the end of the step.
  double theta_new = theta;
  if (ramp_done < ramp_total) {
    ++ramp_done;
    theta_new = theta_from + (theta_to - theta_from) * double(ramp_done) / ramp_total;
  }
  if (!dynamic && ramp_done < ramp_total) {  // static: go to the target at once
    ramp_done = ramp_total;
    theta_new = theta_to;
  }
  const double t_new = dynamic ? t + dt : t;
  const double plate_new = plate_override ? *plate_override : plate_at(t_new);

  std::string why;
  // Guess: free nodes keep their velocity (dynamic) or rest (static); base nodes prescribed;
  // (fast) contact nodes active in the last step land on the plate.
  const Eigen::Matrix3d Gb = base_rotation(theta_new);
  Eigen::VectorXd vg = dynamic ? v : Eigen::VectorXd::Zero(3 * n);
  // A change of the base's angular velocity carries the body along rigidly to first order.
  const double omega_new = dynamic ? (theta_new - theta) / dt : 0.0;
  if (dynamic && solver.method == StepMethod::Fast && omega_new != omega_last) {
    const Eigen::Vector3d dw(0.0, omega_new - omega_last, 0.0);
    for (int i = 0; i < n; ++i) vg.segment<3>(3 * i) += dw.cross(x.segment<3>(3 * i));
  }
  // The last step's velocity change is assumed to go on (linear extrapolation, including a
  // base turn's rigid change again, which measured best: 4.28 -> 3.70 CG iterations per step
  // under policy-like turns, `bench fem --turn-deg 5` on j41).
  if (dynamic && solver.method == StepMethod::Fast) vg += v - v_prev;
  for (int bn : model->base_nodes)
    vg.segment<3>(3 * bn) = (Gb * model->rest_positions.segment<3>(3 * bn) - x.segment<3>(3 * bn)) / dt;
  const bool exact = solver.method == StepMethod::Exact;
  if (!exact)
    for (std::size_t c = 0; c < model->contact_nodes.size(); ++c)
      if (was_active[c]) vg[3 * model->contact_nodes[c] + 2] = (plate_new - x[3 * model->contact_nodes[c] + 2]) / dt;
  Eigen::VectorXd kv;
  const StepStatus fs = exact ? force_pass(x, f, why) : force_pass(x, f, why, &vg, &kv, 1e-6);
  if (fs != StepStatus::Ok) return fail(fs, why);
  double c_m, c_k;
  coefficients(dt, c_m, c_k);
  // Right-hand side b = M v + dt f (all DOFs).
  Eigen::VectorXd b = dt * f;
  if (dynamic)
    for (int i = 0; i < n; ++i) b.segment<3>(3 * i) += model->lumped_mass[i] * v.segment<3>(3 * i);
  Eigen::VectorXd vnew;
  const StepResult sr = exact ? exact_solve(vg, b, plate_new, dt, c_m, c_k, vnew)
                              : fast_solve(vg, kv, b, plate_new, dt, c_m, c_k, vnew);
  if (!sr.ok()) return sr;
  // Update the state.
  Eigen::VectorXd xnew = x + dt * vnew;
  for (int bn : model->base_nodes) xnew.segment<3>(3 * bn) = Gb * model->rest_positions.segment<3>(3 * bn);
  if (!xnew.allFinite() || !vnew.allFinite()) return fail(StepStatus::NonFinite, "non-finite positions or velocities");
  x = std::move(xnew);
  v_prev = v;
  v = dynamic ? std::move(vnew) : Eigen::VectorXd::Zero(3 * n);
  t = t_new;
  omega_last = dynamic ? (theta_new - theta) / dt : 0.0;
  theta = theta_new;
  return sr;
}

// ---------------------------------------------------------------- public wrapper
Simulator::Simulator(std::shared_ptr<const Model> model, const SceneConfig& scene, const SolverConfig& solver)
    : impl_(std::make_unique<Impl>(std::move(model), scene, solver)) {}
Simulator::~Simulator() = default;
Simulator::Simulator(Simulator&&) noexcept = default;
Simulator& Simulator::operator=(Simulator&&) noexcept = default;

void Simulator::reset() { impl_->reset(); }

void Simulator::drop_stored_factors() {
  Impl& m = *impl_;
  const auto drop = [](Impl::Reference& r) {
    r.factor.clear();
    r.node_rot = {};
    r.dt = 0.0;
    r.cols = {};
    r.valid = false;
  };
  // The references at the reset placement stay: every episode of the design starts from them
  // (they are the same whatever the episodes before), so keeping them is what reuse saves.
  for (Impl::RefSlot& sl : m.slots) {
    drop(sl.cur);
    sl.use = Impl::RefSlot::Use::Rest;
  }
  drop(m.settled);
  m.settled_token.reset();
  m.exact_factor.clear();
  m.exact_analysed = false;
}

StepResult Simulator::settle(SettleFor purpose) {
  Impl& m = *impl_;
  StepResult last;
  const int n = std::max(1, m.scene.settle_steps);
  for (int s = 1; s <= n; ++s) {
    last = m.advance(false, m.z_touch + (m.plate_at(0.0) - m.z_touch) * double(s) / n);
    if (!last.ok()) return last;
  }
  // A few extra static iterations at the final height.
  for (int s = 0; s < 5; ++s) {
    last = m.advance(false);
    if (!last.ok()) return last;
  }
  // Fast: factorise the dynamic system at the settled state — the operating point of the
  // episode is a far better preconditioner than the straight rest placement. A settle for a
  // reading leaves no dynamic step to precondition.
  if (m.solver.method == StepMethod::Fast && purpose == SettleFor::Episode) {
    std::string why;
    Eigen::VectorXd ff;
    const StepStatus fs = m.force_pass(m.x, ff, why);
    if (fs != StepStatus::Ok) return m.fail(fs, why);
    Impl::RefSlot& sl = m.slot(true);
    m.settled_token.reset();
    if (!m.build_reference(m.settled, m.solver.dt_s)) return m.fail(StepStatus::SolverFailure, "CHOLMOD factorisation at the settled state failed");
    m.settled_token = std::make_shared<const int>(0);
    sl.use = Impl::RefSlot::Use::Settled;
    last.refactorised = true;
  }
  // Dynamic time starts at t = 0 with the plate at z0 + U sin(phase).
  return last;
}

StepResult Simulator::static_step() { return impl_->advance(false); }
StepResult Simulator::step() { return impl_->advance(true); }

void Simulator::set_pressures_kPa(double p0, double p1) {
  impl_->pressures_Pa = {1e3 * p0, impl_->model->chamber_count() >= 2 ? 1e3 * p1 : 0.0};
}

void Simulator::set_base_angle_target(double theta_rad, int n_substeps) {
  Impl& m = *impl_;
  m.theta_from = m.theta;
  m.theta_to = theta_rad;
  m.ramp_total = std::max(1, n_substeps);
  m.ramp_done = 0;
}

void Simulator::set_base_angle(double theta_rad) { set_base_angle_target(theta_rad, 1); }

void Simulator::set_plate_mean_z(double z0_mm) { impl_->z_mean = z0_mm; }

void Simulator::set_plate_phase(double phase_rad) { impl_->scene.plate_phase_rad = phase_rad; }

double Simulator::time() const { return impl_->t; }
double Simulator::theta() const { return impl_->theta; }
double Simulator::plate_z() const { return impl_->plate_at(impl_->t); }
double Simulator::plate_touch_z() const { return impl_->z_touch; }
const Eigen::VectorXd& Simulator::positions() const { return impl_->x; }
const Eigen::VectorXd& Simulator::velocities() const { return impl_->v; }
const std::vector<std::pair<int, double>>& Simulator::contact_forces() const { return impl_->contacts; }

const Model& Simulator::model() const { return *impl_->model; }
const SceneConfig& Simulator::scene() const { return impl_->scene; }
const SolverConfig& Simulator::solver() const { return impl_->solver; }
int Simulator::factorisations() const { return impl_->factorisations; }

}  // namespace codesign::fem
