// Faces of touching solids: the two boxes' faces in the shared plane are found, nothing else.
#include <polyloc/map/coincident_faces.hpp>

#include <gtest/gtest.h>

using namespace polyloc;

TEST(CoincidentFaces, TouchingBoxesShareOnlyTheirContactFaces) {
  Mesh m;
  m.addBox({0, 0, 0}, {1, 1, 1}, 1);
  m.addBox({1, 0.25, 0}, {2, 0.75, 0.5}, 2);  // against the first box's x = 1 face, smaller
  m.addBox({3, 0, 0}, {4, 1, 1}, 3);          // apart: nothing shared
  const CoincidentFaces c(m);
  size_t flagged = 0;
  for (uint32_t t = 0; t < m.triangles.size(); ++t) {
    if (!c.has(t)) continue;
    ++flagged;
    const Eigen::Vector3f n = m.triangleNormal(t);
    EXPECT_NEAR(std::abs(n.x()), 1.f, 1e-6f) << t;  // only faces in the plane x = 1
    for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(m.vertices[m.triangles[t][k]].x(), 1.f) << t;
    EXPECT_LT(t, 24u) << "the third box touches nothing";
  }
  EXPECT_EQ(flagged, 4u);  // two triangles of each box's face at x = 1
  EXPECT_EQ(c.triangles(), 4u);
  // The first box's x = 1 face is covered only where the second box stands against it.
  bool covered_inside = false, covered_outside = false;
  for (uint32_t t = 0; t < 12; ++t) {
    covered_inside = covered_inside || c.covers(t, {1.f, 0.5f, 0.25f});
    covered_outside = covered_outside || c.covers(t, {1.f, 0.1f, 0.9f});
  }
  EXPECT_TRUE(covered_inside);
  EXPECT_FALSE(covered_outside);
}

TEST(CoincidentFaces, FacesThatOnlyShareAnEdgeOrFaceTheSameWayAreNotCoincident) {
  Mesh m;
  m.addBox({0, 0, 0}, {1, 1, 1}, 1);
  m.addBox({1, 1, 0}, {2, 2, 1}, 2);  // meets the first along an edge only
  m.addBox({0, 0, 2}, {1, 1, 3}, 3);  // its faces are coplanar with the first's, facing the same way
  const CoincidentFaces c(m);
  EXPECT_FALSE(c.any());
  EXPECT_EQ(c.triangles(), 0u);
}
