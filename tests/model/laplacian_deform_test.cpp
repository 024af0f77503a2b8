// The Laplacian deformation as a mesh routine of its own (issue 27), apart from the 2-D leaf
// that curls with it.
#include "leafdig/model/mesh/laplacian_deform.hpp"

#include <gtest/gtest.h>

#include "leafdig/model/errors.hpp"

namespace m = leafdig::model;

// A kite: centre c = (0, 0), A = (1, 0), B = (0, 2), C = (-1, 0), D = (0, -2), four
// triangles around c. Cotangent weights by hand: edge c-A sees cot 2 at B and cot 2 at D
// (w = 4), edge c-B sees cot 1/2 at A and at C (w = 1); the rim edges see the right angle at
// c (cot 0). Normalised rows: c: z_c - (4 z_A + z_B + 4 z_C + z_D) / 10; each corner: z_i - z_c.
// With the corners held at z = (1, 0, 0, 0) and the flat kite's sigma = 0 in z, the energy
// (z_c - 0.4)^2 + (1 - z_c)^2 + 3 z_c^2 is least at 5 z_c = 0.4 + 1: z_c = 0.28 (the
// harmonic value, from the centre's row alone, would be 0.4; uniform weights 0.25).
TEST(LaplacianDeformation, MatchesTheHandSolvedKite) {
  m::Mesh kite;
  kite.positions = {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {-1, 0, 0}, {0, -2, 0}};
  kite.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 1}};
  const auto out = m::laplacianDeform(kite, {{1, {1, 0, 1}}, {2, {0, 2, 0}}, {3, {-1, 0, 0}}, {4, {0, -2, 0}}});
  EXPECT_NEAR(out[0].z(), 0.28, 1e-12);
  EXPECT_NEAR(out[0].x(), 0.0, 1e-12);  // the in-plane differential coordinates are kept
  EXPECT_NEAR(out[0].y(), 0.0, 1e-12);
  EXPECT_EQ(out[1], Eigen::Vector3d(1, 0, 1));
  // Nothing held: the mesh could float anywhere, and says so.
  EXPECT_THROW((void)m::laplacianDeform(kite, {}), m::InputError);
}

// Differential coordinates do not change under a translation: hold every rim vertex moved by
// the same vector and the free vertices follow by exactly that vector.
TEST(LaplacianDeformation, ATranslatedRimTranslatesTheWholeMesh) {
  m::Mesh grid;
  const int n = 5;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) grid.positions.emplace_back(i * 1.0, j * 1.5 + 0.1 * i * i, 0.05 * i * j);
  const auto at = [&](int i, int j) { return static_cast<std::uint32_t>(j * n + i); };
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      grid.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      grid.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  const Eigen::Vector3d shift(3.0, -2.0, 7.5);
  std::vector<std::pair<std::uint32_t, Eigen::Vector3d>> handles;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      if (i == 0 || j == 0 || i == n - 1 || j == n - 1)
        handles.emplace_back(at(i, j), grid.positions[at(i, j)] + shift);
  const auto out = m::laplacianDeform(grid, handles);
  ASSERT_EQ(out.size(), grid.positions.size());
  for (std::size_t v = 0; v < out.size(); ++v) EXPECT_LT((out[v] - (grid.positions[v] + shift)).norm(), 1e-9) << v;
}

// Two triangles apart, one of them held: the other could float anywhere, and the error says
// which vertex and what to do.
TEST(LaplacianDeformation, APartWithNoHandleIsRefusedByName) {
  m::Mesh two;
  two.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 0, 0}, {6, 0, 0}, {5, 1, 0}};
  two.triangles = {{0, 1, 2}, {3, 4, 5}};
  try {
    (void)m::laplacianDeform(two, {{0, {0, 0, 0}}, {1, {1, 0, 0}}, {2, {0, 1, 0}}});
    FAIL() << "a floating part was accepted";
  } catch (const m::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("vertex 3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("hold at least one vertex of every part"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)m::laplacianDeform(two, {{0, {0, 0, 0}}, {99, {0, 0, 0}}}), m::InputError);  // out of range
}
