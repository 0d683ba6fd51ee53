#include "fem/whisker_model.hpp"

#include "fem/design.hpp"

namespace codesign::fem {

namespace {

WhiskerGeometry geometry_of(int design_index, const WhiskerModelSpec& spec) {
  WhiskerGeometry g = spec.geometry;
  g.design = design_from_index(design_index);
  return g;
}

// Fibre layout and build_model: the steps after meshing.
std::shared_ptr<const Model> model_of_mesh(const WhiskerGeometry& g, TetMesh mesh, const WhiskerModelSpec& spec) {
  ModelOptions mo = spec.model;
  mo.fibre_polylines.clear();
  mo.fibre_chains.clear();
  if (spec.fibres.count > 0 && mo.fibre_axial_stiffness_uN > 0.0)
    for (FibreChain& c : layout_fibres(mesh, g, spec.fibres)) mo.fibre_chains.push_back(std::move(c.points));
  return build_model(std::move(mesh), mo);
}

}  // namespace

std::shared_ptr<const Model> build_whisker_model(int design_index, const WhiskerModelSpec& spec) {
  return whisker_model_from_mesh(design_index, mesh_whisker(geometry_of(design_index, spec), spec.mesh), spec);
}

std::shared_ptr<const Model> build_whisker_model(const Design& design, const WhiskerModelSpec& spec) {
  WhiskerGeometry g = spec.geometry;
  g.design = design;
  return model_of_mesh(g, mesh_whisker(g, spec.mesh), spec);
}

std::shared_ptr<const Model> whisker_model_from_mesh(int design_index, TetMesh mesh, const WhiskerModelSpec& spec) {
  return model_of_mesh(geometry_of(design_index, spec), std::move(mesh), spec);
}

}  // namespace codesign::fem
