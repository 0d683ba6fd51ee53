// SimulatorPool's meshes from elsewhere: a pool given another pool's mesh of a design builds that
// design's model without meshing it (take_meshed stays empty, the build counts as adopted), and the
// model is the other pool's bit for bit (fem::whisker_model_from_mesh, tests/fem/whisker_model_test.cpp).
#include <gtest/gtest.h>

#include <stdexcept>

#include "codesign/simulator_pool.hpp"

namespace {

using codesign::core::SimulatorPool;
namespace fem = codesign::fem;

SimulatorPool make_pool() { return SimulatorPool(fem::WhiskerModelSpec{}, fem::SceneConfig{}, fem::SolverConfig{}); }

TEST(SimulatorPool, AdoptsAnotherPoolsMeshInsteadOfMeshing) {
  SimulatorPool a = make_pool(), b = make_pool();
  EXPECT_TRUE(a.take_meshed().empty());
  EXPECT_FALSE(a.has_model(21));
  const auto meshed = a.model(21);
  a.model(21);  // built once
  EXPECT_TRUE(a.has_model(21));
  EXPECT_EQ(a.take_meshed(), std::vector<int>{21});
  EXPECT_TRUE(a.take_meshed().empty());  // taken
  EXPECT_EQ(a.build_stats().models, 1);
  EXPECT_EQ(a.build_stats().adopted, 0);

  EXPECT_TRUE(b.adopt_mesh(21, meshed->mesh));
  EXPECT_FALSE(b.adopt_mesh(21, meshed->mesh));  // has it: nothing happens
  const auto adopted = b.model(21);
  EXPECT_TRUE(b.take_meshed().empty());
  const SimulatorPool::BuildStats s = b.build_stats();
  EXPECT_EQ(s.models, 0);
  EXPECT_EQ(s.adopted, 1);
  EXPECT_EQ(s.seconds, s.adopt_seconds);
  EXPECT_EQ(s.seconds_per_model(), 0.0);
  EXPECT_TRUE(adopted->rest_positions == meshed->rest_positions);
  ASSERT_EQ(adopted->k0.size(), meshed->k0.size());
  for (std::size_t e = 0; e < adopted->k0.size(); ++e) ASSERT_TRUE(adopted->k0[e] == meshed->k0[e]) << "tet " << e;
  EXPECT_EQ(adopted->fibres.size(), meshed->fibres.size());

  // A simulator of the adopted model counts as a simulator, not as a model.
  b.release(21, b.acquire(21));
  EXPECT_EQ(b.build_stats().simulators, 1);
  EXPECT_GE(b.build_stats().seconds_per_simulator(), 0.0);
}

TEST(SimulatorPool, RefusesAMeshForADesignOffTheGrid) {
  SimulatorPool a = make_pool();
  EXPECT_THROW(a.adopt_mesh(-1, fem::TetMesh{}), std::out_of_range);
  EXPECT_THROW(a.adopt_mesh(fem::kDesignCount, fem::TetMesh{}), std::out_of_range);
  EXPECT_THROW(a.adopt_mesh(3, fem::TetMesh{}), std::invalid_argument);  // no tets
  EXPECT_FALSE(a.has_model(3));
  EXPECT_FALSE(a.has_model(fem::kDesignCount));
}

}  // namespace
