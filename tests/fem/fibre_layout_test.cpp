#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "fem/design.hpp"
#include "fem/fibre_layout.hpp"
#include "fem/mesh_ops.hpp"
#include "fem/whisker_mesh.hpp"

using namespace codesign::fem;

TEST(FibreLayout, PointsAreEmbeddedOnTheHelix) {
  for (int j : {0, 21, 63, 109}) {
    WhiskerGeometry g;
    g.design = design_from_index(j);
    const TetMesh m = mesh_whisker(g);
    const FibreLayoutOptions opt;
    const auto lines = fibre_polylines(g, opt);
    const auto chains = embed_polylines(m, lines);
    ASSERT_EQ(chains.size(), static_cast<std::size_t>(opt.count));
    for (std::size_t k = 0; k < chains.size(); ++k) {
      ASSERT_EQ(chains[k].points.size(), lines[k].size());
      // points_per_turn per turn, rounded up to a whole number of segments.
      const double segments = g.design.chamber_length_mm / opt.pitch_mm * opt.points_per_turn;
      EXPECT_GE(static_cast<double>(lines[k].size() - 1), segments - 1e-6);
      EXPECT_LT(static_cast<double>(lines[k].size() - 1), segments + 1);
      for (std::size_t i = 0; i < chains[k].points.size(); ++i) {
        const EmbeddedPoint& e = chains[k].points[i];
        ASSERT_GE(e.tet, 0);
        EXPECT_GE(e.weights.minCoeff(), -1e-9);
        EXPECT_NEAR(e.weights.sum(), 1.0, 1e-12);
        Eigen::Vector3d p = Eigen::Vector3d::Zero();
        for (int a = 0; a < 4; ++a) p += e.weights[a] * m.nodes[m.tets[e.tet][a]];
        EXPECT_LT((p - lines[k][i]).norm(), 1e-9);
        // On the intended helix: radius R(x) - inset, x within the chamber region.
        EXPECT_NEAR(std::hypot(p.y(), p.z()), g.outer_radius(p.x()) - opt.radial_inset_mm, 1e-9);
        EXPECT_GE(p.x(), g.chamber_start() - 1e-9);
        EXPECT_LE(p.x(), g.chamber_end() + 1e-9);
      }
      // Ends of the chamber region are covered.
      EXPECT_NEAR(lines[k].front().x(), g.chamber_start(), 1e-12);
      EXPECT_NEAR(lines[k].back().x(), g.chamber_end(), 1e-12);
    }
    // Counter-wound: the angle grows along +x for fibre 0 and falls for fibre 1.
    auto angle = [](const Eigen::Vector3d& p) { return std::atan2(p.z(), p.y()); };
    auto dphi = [&](const std::vector<Eigen::Vector3d>& l) {
      double d = angle(l[1]) - angle(l[0]);
      return std::remainder(d, 2 * std::numbers::pi);
    };
    EXPECT_GT(dphi(lines[0]), 0.0);
    EXPECT_LT(dphi(lines[1]), 0.0);
    // One segment advances l / segments along x, i.e. 2π (l / segments) / pitch in angle.
    const double seg = static_cast<double>(lines[0].size() - 1);
    EXPECT_NEAR(std::abs(dphi(lines[0])), 2 * std::numbers::pi * g.design.chamber_length_mm / seg / opt.pitch_mm, 1e-9);
  }
}

TEST(FibreLayout, RejectsBadOptionsAndPointsOutsideTheMesh) {
  WhiskerGeometry g;
  FibreLayoutOptions bad;
  bad.pitch_mm = 0;
  EXPECT_THROW(fibre_polylines(g, bad), std::invalid_argument);
  bad = {};
  bad.radial_inset_mm = g.design.wall_mm;  // would sit on the cavity
  EXPECT_THROW(fibre_polylines(g, bad), std::invalid_argument);
  const TetMesh m = mesh_whisker(g);
  const std::vector<std::vector<Eigen::Vector3d>> outside{{Eigen::Vector3d(50, 20, 0)}};
  EXPECT_THROW(embed_polylines(m, outside), std::runtime_error);
  FibreLayoutOptions none;
  none.count = 0;
  EXPECT_TRUE(layout_fibres(m, g, none).empty());
}

TEST(TetLocator, AgreesWithBruteForce) {
  WhiskerGeometry g;
  g.design = design_from_index(63);
  const TetMesh m = mesh_whisker(g);
  const TetLocator loc(m);
  // Tet centroids are inside exactly their own tet.
  for (int t = 0; t < static_cast<int>(m.tets.size()); t += 7) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int v : m.tets[t]) c += 0.25 * m.nodes[v];
    EXPECT_EQ(loc.locate(c), t);
  }
  // Points in a cavity or outside are in no tet.
  EXPECT_EQ(loc.locate(Eigen::Vector3d(0.5 * (g.chamber_start() + g.chamber_end()), 0, 0.5 * g.cavity_radius() + 0.25 * g.design.wall_mm)), -1);
  EXPECT_EQ(loc.locate(Eigen::Vector3d(50, 30, 0)), -1);
}
