#include "fem/model_scaling.hpp"

#include <cmath>
#include <stdexcept>

namespace codesign::fem {

std::shared_ptr<const Model> scaled_model(const Model& model, const BodyScale& s) {
  for (const double f : {s.youngs_modulus, s.mass, s.damping, s.fibre_stiffness})
    if (!(std::isfinite(f) && f > 0.0)) throw std::invalid_argument("scaled_model: a factor is not positive and finite");
  auto m = std::make_shared<Model>(model);
  m->material.youngs_modulus_Pa *= s.youngs_modulus;
  m->material.total_mass_g *= s.mass;
  m->lumped_mass *= s.mass;
  m->material.rayleigh_mass_per_s *= s.damping;
  m->material.rayleigh_stiffness_s *= s.damping;
  for (FibreSpring& f : m->fibres) f.stiffness_uN_per_mm *= s.fibre_stiffness;
  return m;
}

}  // namespace codesign::fem
