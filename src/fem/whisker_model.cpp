#include "fem/whisker_model.hpp"

#include "fem/design.hpp"

namespace codesign::fem {

std::shared_ptr<const Model> build_whisker_model(int design_index, const WhiskerModelSpec& spec) {
  WhiskerGeometry g = spec.geometry;
  g.design = design_from_index(design_index);
  TetMesh mesh = mesh_whisker(g, spec.mesh);
  ModelOptions mo = spec.model;
  mo.fibre_polylines.clear();
  // Fibre springs: wired in when the fibre layout (fem/fibre_layout.hpp) is available.
  return build_model(std::move(mesh), mo);
}

}  // namespace codesign::fem
