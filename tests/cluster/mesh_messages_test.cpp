// The wire format of designs' meshes between ranks: what one rank packs is what another unpacks,
// coordinates bit for bit; malformed messages are refused before any index is used.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <stdexcept>

#include "cluster/mesh_messages.hpp"
#include "fem/design.hpp"

namespace {

using namespace codesign;
using namespace codesign::cluster;

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// A small mesh with every part: 5 nodes (odd coordinates among them), 2 tets, faces on the base,
// the tip and two chambers (one of them empty).
fem::TetMesh small_mesh() {
  fem::TetMesh m;
  m.nodes = {{0.0, 0.0, 0.0}, {1.0, -0.0, 0.0}, {0.0, 1e-310, 0.0}, {0.1, 0.2, 0.30000000000000004}, {1.0, 1.0, 1.0}};
  m.tets = {{0, 1, 2, 3}, {1, 2, 3, 4}};
  m.base_faces = {{0, 2, 1}};
  m.tip_faces = {{1, 4, 3}, {2, 3, 4}};
  m.chamber_faces = {{{0, 1, 3}}, {}};
  return m;
}

TEST(MeshMessages, MeshesRoundTripBitForBit) {
  const fem::TetMesh a = small_mesh();
  fem::TetMesh b = small_mesh();
  b.chamber_faces.clear();
  b.nodes.push_back({-2.5, 3.0, 7.0});
  const std::vector<double> v = pack_meshes({109, 0}, {&a, &b});
  // 1 + per mesh 6 + chambers, 3 per node, 4 per tet, 3 per face.
  EXPECT_EQ(v.size(), 1u + (6 + 2 + 15 + 8 + 3 + 6 + 3) + (6 + 18 + 8 + 3 + 6));
  const std::vector<DesignMesh> back = unpack_meshes(v);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0].design, 109);
  EXPECT_EQ(back[1].design, 0);
  for (const auto& [sent, got] : {std::pair{&a, &back[0].mesh}, {&b, &back[1].mesh}}) {
    ASSERT_EQ(got->nodes.size(), sent->nodes.size());
    for (std::size_t i = 0; i < sent->nodes.size(); ++i)
      for (int c = 0; c < 3; ++c) EXPECT_TRUE(same_bits(got->nodes[i][c], sent->nodes[i][c])) << i << " " << c;
    EXPECT_EQ(got->tets, sent->tets);
    EXPECT_EQ(got->base_faces, sent->base_faces);
    EXPECT_EQ(got->tip_faces, sent->tip_faces);
    EXPECT_EQ(got->chamber_faces, sent->chamber_faces);
  }
  EXPECT_TRUE(unpack_meshes(pack_meshes({}, {})).empty());
}

TEST(MeshMessages, MalformedMessagesAreRefused) {
  const fem::TetMesh a = small_mesh();
  EXPECT_THROW(pack_meshes({1, 2}, {&a}), std::invalid_argument);
  EXPECT_THROW(pack_meshes({1}, {nullptr}), std::invalid_argument);
  const std::vector<double> good = pack_meshes({5}, {&a});
  ASSERT_NO_THROW(unpack_meshes(good));
  EXPECT_THROW(unpack_meshes({}), std::invalid_argument);  // not even a count
  for (std::size_t cut = 1; cut < good.size(); ++cut)      // ends early anywhere
    EXPECT_THROW(unpack_meshes(std::vector<double>(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(cut))),
                 std::invalid_argument)
        << cut;
  std::vector<double> longer = good;
  longer.push_back(0.0);
  EXPECT_THROW(unpack_meshes(longer), std::invalid_argument);  // goes on after its last mesh
  // Where the fields sit in `good`: [0] count, [1] design, [2..6] counts, [7..8] the chambers'
  // face counts, [9..23] coordinates, [24..31] tets.
  const auto with = [&](std::size_t at, double x) {
    std::vector<double> v = good;
    v[at] = x;
    return v;
  };
  for (double bad : {-1.0, 0.5, std::numeric_limits<double>::quiet_NaN(), 1e300}) {
    EXPECT_THROW(unpack_meshes(with(0, bad)), std::invalid_argument) << bad;
    EXPECT_THROW(unpack_meshes(with(2, bad)), std::invalid_argument) << bad;
    EXPECT_THROW(unpack_meshes(with(24, bad)), std::invalid_argument) << bad;
  }
  EXPECT_THROW(unpack_meshes(with(1, fem::kDesignCount)), std::invalid_argument);  // no such design
  EXPECT_THROW(unpack_meshes(with(24, 5.0)), std::invalid_argument);               // node 5 of 0..4
  EXPECT_THROW(unpack_meshes(with(good.size() - 1, 5.0)), std::invalid_argument);  // a chamber face's node
  EXPECT_THROW(unpack_meshes(with(2, 4.0)), std::invalid_argument);  // 4 nodes: the tets name node 4
  EXPECT_NO_THROW(unpack_meshes(with(9, std::numeric_limits<double>::quiet_NaN())));  // coordinates are not checked
}

}  // namespace
