// whisker_model_from_mesh: given the mesh that meshing makes for a design, the model and its
// simulation are build_whisker_model's bit for bit (the MPI backend sends a design's mesh to the
// ranks that have not meshed it, cluster/mpi_env_pool.hpp).
#include <gtest/gtest.h>

#include <stdexcept>

#include "fem/design.hpp"
#include "fem/simulator.hpp"
#include "fem/whisker_model.hpp"

namespace {

using namespace codesign::fem;

TetMesh mesh_of(int design, const WhiskerModelSpec& spec) {
  WhiskerGeometry g = spec.geometry;
  g.design = design_from_index(design);
  return mesh_whisker(g, spec.mesh);
}

bool same_point(const EmbeddedPoint& a, const EmbeddedPoint& b) { return a.tet == b.tet && a.weights == b.weights; }

void expect_same_model(const Model& a, const Model& b) {
  EXPECT_EQ(a.mesh.nodes, b.mesh.nodes);
  EXPECT_EQ(a.mesh.tets, b.mesh.tets);
  EXPECT_EQ(a.mesh.chamber_faces, b.mesh.chamber_faces);
  ASSERT_EQ(a.rest.size(), b.rest.size());
  for (std::size_t e = 0; e < a.rest.size(); ++e)
    ASSERT_TRUE(a.rest[e].grad == b.rest[e].grad && a.rest[e].dm_inv == b.rest[e].dm_inv &&
                a.rest[e].volume == b.rest[e].volume)
        << "tet " << e;
  EXPECT_TRUE(a.rest_positions == b.rest_positions);
  EXPECT_TRUE(a.lumped_mass == b.lumped_mass);
  EXPECT_EQ(a.volume_mm3, b.volume_mm3);
  EXPECT_EQ(a.contact_nodes, b.contact_nodes);
  EXPECT_EQ(a.chamber_tets, b.chamber_tets);
  ASSERT_EQ(a.fibres.size(), b.fibres.size());
  for (std::size_t k = 0; k < a.fibres.size(); ++k) {
    EXPECT_TRUE(same_point(a.fibres[k].a, b.fibres[k].a) && same_point(a.fibres[k].b, b.fibres[k].b)) << "fibre " << k;
    EXPECT_EQ(a.fibres[k].rest_length_mm, b.fibres[k].rest_length_mm);
    EXPECT_EQ(a.fibres[k].stiffness_uN_per_mm, b.fibres[k].stiffness_uN_per_mm);
  }
}

TEST(WhiskerModel, FromItsMeshIsTheModelBuiltFromTheDesignBitForBit) {
  const WhiskerModelSpec spec;
  for (int design : {21, 63}) {  // one chamber, two chambers
    SCOPED_TRACE(design);
    const auto built = build_whisker_model(design, spec);
    const auto from_mesh = whisker_model_from_mesh(design, mesh_of(design, spec), spec);
    ASSERT_FALSE(built->fibres.empty());  // the layout ran in both
    expect_same_model(*built, *from_mesh);
    // And so does a simulation on each: settle, then steps with the base turning.
    Simulator a(built, SceneConfig{}, SolverConfig{}), b(from_mesh, SceneConfig{}, SolverConfig{});
    for (Simulator* s : {&a, &b}) {
      s->set_pressures_kPa(6.0, design >= 55 ? 3.0 : 0.0);
      s->set_plate_phase(0.5);
      ASSERT_TRUE(s->settle().ok());
      for (int k = 0; k < 20; ++k) {
        if (k % 5 == 0) s->set_base_angle_target(s->theta() + 0.04, 5);
        ASSERT_TRUE(s->step().ok());
      }
    }
    EXPECT_TRUE(a.positions() == b.positions());
    EXPECT_EQ(a.sensors().contact_force_mN, b.sensors().contact_force_mN);
  }
}

TEST(WhiskerModel, FromAMeshRefusesADesignOffTheGrid) {
  const WhiskerModelSpec spec;
  EXPECT_THROW(whisker_model_from_mesh(kDesignCount, mesh_of(21, spec), spec), std::out_of_range);
  EXPECT_THROW(whisker_model_from_mesh(21, TetMesh{}, spec), std::invalid_argument);
}

}  // namespace
