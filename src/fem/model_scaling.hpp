#pragma once
// A design's body with its physical constants off their nominal values, on the same mesh: what
// one episode under physical uncertainty ([randomize], core/physics_randomization.hpp) simulates.
// Young's modulus enters the simulation only through the material's Lamé parameters (the rest
// data are geometry), the mass through the lumped masses, so a scaled model needs no meshing:
// it is a copy of the nominal one with a few numbers changed.
#include <memory>

#include "fem/model.hpp"

namespace codesign::fem {

// Factors on the nominal values (1: as meshed).
struct BodyScale {
  bool operator==(const BodyScale&) const = default;
  double youngs_modulus = 1.0;  // E
  double mass = 1.0;            // total and lumped masses
  double damping = 1.0;         // both Rayleigh coefficients
  double fibre_stiffness = 1.0; // every fibre spring's stiffness
  bool nominal() const { return *this == BodyScale{}; }
};

// `model` with E, the masses, the Rayleigh coefficients and the fibre springs' stiffness scaled;
// everything else (mesh, rest data, node sets, sensing region) as it is. Throws
// std::invalid_argument for a factor that is not positive and finite.
std::shared_ptr<const Model> scaled_model(const Model& model, const BodyScale& scale);

}  // namespace codesign::fem
