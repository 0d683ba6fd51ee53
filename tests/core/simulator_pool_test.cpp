// SimulatorPool's meshes from elsewhere, and the bound on its idle simulators.
// Meshes from elsewhere: a pool given another pool's mesh of a design builds that
// design's model without meshing it (take_meshed stays empty, the build counts as adopted), and the
// model is the other pool's bit for bit (fem::whisker_model_from_mesh, tests/fem/whisker_model_test.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

#include "core/simulator_pool.hpp"

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
  ASSERT_EQ(adopted->rest.size(), meshed->rest.size());
  for (std::size_t e = 0; e < meshed->rest.size(); ++e)
    ASSERT_TRUE(adopted->rest[e].grad == meshed->rest[e].grad && adopted->rest[e].volume == meshed->rest[e].volume) << "tet " << e;
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

// The pool's memory follows what the run uses now: idle simulators never exceed the most leased
// at once, and a return over that bound destroys the one returned longest ago.
TEST(SimulatorPool, IdleSimulatorsNeverExceedTheMostLeasedAtOnce) {
  SimulatorPool pool = make_pool();
  EXPECT_EQ(pool.idle_limit(), 1u);  // nothing leased yet: the bound is its floor
  // Three environments holding designs that come and go, as a run's iterations draw them.
  const std::vector<std::vector<int>> draws = {{1, 1, 2}, {2, 3, 3}, {4, 1, 2}, {4, 4, 4}, {5, 6, 1}, {1, 1, 1}};
  std::vector<std::pair<int, std::unique_ptr<fem::Simulator>>> held(3);
  int max_idle = 0;
  for (const auto& draw : draws) {
    for (std::size_t e = 0; e < held.size(); ++e) {
      if (held[e].second && held[e].first == draw[e]) continue;  // the environment keeps its design
      pool.release(held[e].first, std::move(held[e].second));
      held[e] = {draw[e], pool.acquire(draw[e])};
      ASSERT_LE(pool.idle(), pool.idle_limit());
      max_idle = std::max(max_idle, static_cast<int>(pool.idle()));
    }
    EXPECT_EQ(pool.leased(), 3u);
  }
  EXPECT_EQ(pool.idle_limit(), 3u);  // three environments, never more leased at once
  for (auto& [design, sim] : held) pool.release(design, std::move(sim));
  EXPECT_EQ(pool.leased(), 0u);
  EXPECT_EQ(pool.idle(), 3u);  // the last three returns; every older idle simulator was destroyed
  EXPECT_EQ(max_idle, 3);      // the bound was reached, so eviction was exercised
}

TEST(SimulatorPool, ReturnOverTheBoundDestroysTheOneReturnedLongestAgo) {
  SimulatorPool pool = make_pool();
  auto a = pool.acquire(1), b = pool.acquire(2);  // two leased at once: the bound is 2
  pool.release(1, std::move(a));
  pool.release(2, std::move(b));
  auto c = pool.acquire(3);
  pool.release(3, std::move(c));  // three idle > 2: design 1's, returned first, goes
  EXPECT_EQ(pool.idle(), 2u);
  const int built = pool.build_stats().simulators;
  EXPECT_EQ(built, 3);
  auto again2 = pool.acquire(2);  // still idle: reused
  EXPECT_EQ(pool.build_stats().simulators, built);
  auto again1 = pool.acquire(1);  // was destroyed: built anew
  EXPECT_EQ(pool.build_stats().simulators, built + 1);
  pool.release(2, std::move(again2));
  pool.release(1, std::move(again1));
  EXPECT_LE(pool.idle(), pool.idle_limit());
}

TEST(SimulatorPool, AModelUnaskedForAWhileIsDroppedAndMeshedAgainToTheSameBits) {
  SimulatorPool pool = make_pool();
  const std::shared_ptr<const fem::Model> first = pool.model(1);  // kept here to compare
  {
    auto a = pool.acquire(1), b = pool.acquire(2);  // two leased at once: idle bound 2
    pool.release(1, std::move(a));
    pool.release(2, std::move(b));
  }
  const std::uint64_t window = pool.model_keep_window();
  EXPECT_EQ(window, SimulatorPool::kModelKeepRounds * static_cast<std::uint64_t>(fem::kDesignCount));
  // Two environments alternating between designs 3 and 4: their returns evict 1's and 2's idle
  // simulators at once, and after `window` requests without 1 or 2 their models go too.
  int requests = 2;
  while (static_cast<std::uint64_t>(requests) <= window + 2) {
    auto c = pool.acquire(3), d = pool.acquire(4);
    requests += 2;
    pool.release(3, std::move(c));
    pool.release(4, std::move(d));
    if (static_cast<std::uint64_t>(requests) <= window + 1) {
      EXPECT_TRUE(pool.has_model(1)) << requests;
    }
  }
  EXPECT_FALSE(pool.has_model(1));
  EXPECT_FALSE(pool.has_model(2));
  EXPECT_TRUE(pool.has_model(3));
  EXPECT_TRUE(pool.has_model(4));
  EXPECT_EQ(pool.models_held(), 2u);
  EXPECT_EQ(pool.build_stats().dropped, 2);
  // Asked for again: meshed again, bit for bit the model it had.
  const int meshed = pool.build_stats().models;
  const std::shared_ptr<const fem::Model> again = pool.model(1);
  EXPECT_EQ(pool.build_stats().models, meshed + 1);
  EXPECT_NE(again.get(), first.get());
  EXPECT_TRUE(again->rest_positions == first->rest_positions);
  ASSERT_EQ(again->rest.size(), first->rest.size());
  for (std::size_t e = 0; e < first->rest.size(); ++e)
    ASSERT_TRUE(again->rest[e].grad == first->rest[e].grad && again->rest[e].volume == first->rest[e].volume) << "tet " << e;
  EXPECT_EQ(again->fibres.size(), first->fibres.size());
}

}  // namespace
