#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <numbers>

#include "fem/design.hpp"
#include "fem/mesh_ops.hpp"
#include "fem/mesh_quality.hpp"
#include "fem/whisker_mesh.hpp"
#include "test_util.hpp"

using namespace codesign::fem;

namespace {

WhiskerGeometry geometry_of(int j) {
  WhiskerGeometry g;
  g.design = design_from_index(j);
  return g;
}

}  // namespace

// Acceptance 1: every design meshes and passes the quality checks with the default options.
TEST(WhiskerMesh, All110DesignsMeshAndPassQuality) {
  const auto t0 = std::chrono::steady_clock::now();
  int min_tets = 1 << 30, max_tets = 0;
  for (int j = 0; j < kDesignCount; ++j) {
    const WhiskerGeometry g = geometry_of(j);
    const TetMesh m = mesh_whisker(g);
    const QualityReport r = check_whisker_mesh(m, g);
    EXPECT_TRUE(r.ok()) << "design " << j << ": " << summary(r);
    ASSERT_EQ(static_cast<int>(m.chamber_faces.size()), g.design.n) << "design " << j;
    min_tets = std::min(min_tets, r.tets);
    max_tets = std::max(max_tets, r.tets);
  }
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("all 110 designs: %d..%d tets, %.1f s\n", min_tets, max_tets, s);
}

TEST(WhiskerMesh, DefaultDesignSizeSuitsTheFastStep) {
  const TetMesh m = mesh_whisker(geometry_of(21));
  // The FEM step budget (≤ 1 ms) was set for a mesh of about 1.5k–3k tets.
  EXPECT_GE(m.tets.size(), 1500u);
  EXPECT_LE(m.tets.size(), 3000u);
}

TEST(WhiskerMesh, IsDeterministic) {
  const TetMesh a = mesh_whisker(geometry_of(63));
  const TetMesh b = mesh_whisker(geometry_of(5));
  const TetMesh c = mesh_whisker(geometry_of(63));
  (void)b;
  ASSERT_EQ(a.nodes.size(), c.nodes.size());
  ASSERT_EQ(a.tets, c.tets);
  for (std::size_t i = 0; i < a.nodes.size(); ++i) EXPECT_EQ(a.nodes[i], c.nodes[i]);
}

TEST(WhiskerMesh, TagsLieOnTheirSurfaces) {
  for (int j : {21, 63}) {
    const WhiskerGeometry g = geometry_of(j);
    const TetMesh m = mesh_whisker(g);
    for (const Tri& f : m.base_faces)
      for (int v : f) EXPECT_NEAR(m.nodes[v].x(), 0.0, 1e-9);
    for (const Tri& f : m.tip_faces)
      for (int v : f) EXPECT_NEAR(m.nodes[v].x(), g.length_mm, 1e-9);
    // Areas: base disc π R0², tip disc π R1², as inscribed polygons (bounds in test_util.hpp).
    const auto [base_lo, base_hi] = codesign::test::disc_area_bounds(m, m.base_faces, g.base_radius());
    EXPECT_GE(surface_area(m, m.base_faces), base_lo);
    EXPECT_LE(surface_area(m, m.base_faces), base_hi);
    const auto [tip_lo, tip_hi] = codesign::test::disc_area_bounds(m, m.tip_faces, g.tip_radius());
    EXPECT_GE(surface_area(m, m.tip_faces), tip_lo);
    EXPECT_LE(surface_area(m, m.tip_faces), tip_hi);
    // Outward normals: base points to -x, tip to +x; a closed chamber surface sums to zero.
    EXPECT_LT(vector_area(m, m.base_faces).x(), 0.0);
    EXPECT_GT(vector_area(m, m.tip_faces).x(), 0.0);
    for (std::size_t c = 0; c < m.chamber_faces.size(); ++c) {
      const double area = surface_area(m, m.chamber_faces[c]);
      EXPECT_LT(vector_area(m, m.chamber_faces[c]).norm(), 1e-9 * area);
      for (const Tri& f : m.chamber_faces[c]) {
        for (int v : f) {
          const Eigen::Vector3d& p = m.nodes[v];
          EXPECT_GE(p.x(), g.chamber_start() - 1e-9);
          EXPECT_LE(p.x(), g.chamber_end() + 1e-9);
          EXPECT_LE(std::hypot(p.y(), p.z()), g.cavity_radius() + 1e-9);
          if (g.design.n == 2) {
            EXPECT_GE(c == 0 ? p.z() : -p.z(), 0.5 * g.design.wall_mm - 1e-9);
          }
        }
      }
    }
  }
}

// The volume error is within the faceting bound, and shrinks when the surface is refined, as
// the bound predicts (error ∝ h²: halving every size must cut it to well below 1/2).
TEST(WhiskerMesh, VolumeMatchesCadAndConverges) {
  const WhiskerGeometry g = geometry_of(21);
  MeshOptions coarse;
  MeshOptions fine = coarse;
  fine.max_size_mm *= 0.5;
  fine.radius_factor *= 0.5;
  fine.wall_factor *= 0.5;
  const QualityReport a = check_whisker_mesh(mesh_whisker(g, coarse), g);
  const QualityReport b = check_whisker_mesh(mesh_whisker(g, fine), g);
  EXPECT_TRUE(a.ok()) << summary(a);
  EXPECT_TRUE(b.ok()) << summary(b);
  EXPECT_LE(std::abs(a.volume_error), a.volume_tolerance);
  EXPECT_LE(std::abs(b.volume_error), b.volume_tolerance);
  EXPECT_LT(std::abs(b.volume_error), 0.5 * std::abs(a.volume_error));
  // Facets are chords: the convex outer skin loses more than the cavity, so the mesh is smaller.
  EXPECT_LT(a.volume_error, 0.0);
}

TEST(WhiskerMesh, CylinderPrimitives) {
  const double r = 5, len = 40, h = 2;
  const TetMesh solid = mesh_cylinder(r, len, h);
  const QualityReport qs = check_mesh(solid);
  EXPECT_TRUE(qs.ok()) << summary(qs);
  const double v_cyl = std::numbers::pi * r * r * len;
  EXPECT_LE(std::abs(total_volume(solid) - v_cyl), faceting_volume_bound(solid, boundary_faces(solid)));
  EXPECT_TRUE(solid.chamber_faces.empty());

  const TetMesh tube = mesh_hollow_cylinder(3, 5, len, h);
  const QualityReport qt = check_mesh(tube);
  EXPECT_TRUE(qt.ok()) << summary(qt);
  ASSERT_EQ(tube.chamber_faces.size(), 1u);
  for (const Tri& f : tube.chamber_faces[0])
    for (int v : f) EXPECT_NEAR(std::hypot(tube.nodes[v].y(), tube.nodes[v].z()), 3.0, 1e-6);
  const double v_tube = std::numbers::pi * (25 - 9) * len;
  EXPECT_LE(std::abs(total_volume(tube) - v_tube), faceting_volume_bound(tube, boundary_faces(tube)));
  // Finer mesh → more tets (the convergence tests of the FEM rely on this knob).
  EXPECT_GT(mesh_cylinder(r, len, 0.5 * h).tets.size(), 4 * solid.tets.size());
}

// The checks must be able to fail.
TEST(MeshQuality, DetectsBrokenMeshes) {
  const WhiskerGeometry g = geometry_of(63);
  const TetMesh good = mesh_whisker(g);
  ASSERT_TRUE(check_whisker_mesh(good, g).ok());

  TetMesh inverted = good;
  std::swap(inverted.tets[10][0], inverted.tets[10][1]);
  EXPECT_GT(check_whisker_mesh(inverted, g).inverted, 0);
  EXPECT_FALSE(check_whisker_mesh(inverted, g).ok());

  TetMesh no_chamber = good;
  no_chamber.chamber_faces[1].clear();
  EXPECT_FALSE(check_whisker_mesh(no_chamber, g).ok());

  TetMesh open_chamber = good;
  open_chamber.chamber_faces[0].pop_back();
  const QualityReport ro = check_whisker_mesh(open_chamber, g);
  EXPECT_FALSE(ro.ok());
  EXPECT_GT(ro.chamber_open_edges[0], 0);

  // The mesh of j21 (one large cavity) checked against the CAD of j109 (n = 2, l = 40, w = 4,
  // ~3000 mm³ more solid) must fail the volume comparison. (The faceting bound is ~8 % of the
  // volume at the default resolution, so the volume check catches gross errors such as a
  // missing or wrong cavity; holes and gaps are caught by the topology checks.)
  WhiskerGeometry g21 = g;
  g21.design = design_from_index(21);
  WhiskerGeometry other = g;
  other.design = design_from_index(109);
  const QualityReport rv = check_whisker_mesh(mesh_whisker(g21), other);
  EXPECT_GT(std::abs(rv.volume_error), rv.volume_tolerance) << summary(rv);

  TetMesh split = good;  // two disjoint copies: two components
  const int off = static_cast<int>(split.nodes.size());
  for (const auto& p : good.nodes) split.nodes.push_back(p + Eigen::Vector3d(0, 100, 0));
  for (Tet t : good.tets) {
    for (int& v : t) v += off;
    split.tets.push_back(t);
  }
  EXPECT_EQ(check_mesh(split).components, 2);
  EXPECT_FALSE(check_mesh(split).ok());
}

TEST(MeshQuality, FlatTetFailsShapeThresholds) {
  TetMesh m;
  m.nodes = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0.01}};
  m.tets = {{0, 1, 2, 3}};
  if (tet_volume(m, 0) < 0) std::swap(m.tets[0][2], m.tets[0][3]);
  const QualityReport r = check_mesh(m);
  EXPECT_LT(r.min_dihedral_deg, 5.0);
  EXPECT_LT(r.min_radius_ratio, 0.1);
  EXPECT_FALSE(r.ok());
  // The regular tet: radius ratio 1, all dihedral angles acos(1/3) = 70.53°.
  TetMesh reg;
  reg.nodes = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
  reg.tets = {{0, 1, 2, 3}};
  if (tet_volume(reg, 0) < 0) std::swap(reg.tets[0][2], reg.tets[0][3]);
  const QualityReport q = check_mesh(reg);
  EXPECT_NEAR(q.min_radius_ratio, 1.0, 1e-12);
  EXPECT_NEAR(q.min_dihedral_deg, std::acos(1.0 / 3.0) * 180 / std::numbers::pi, 1e-9);
}
