// Faces of touching solids: the two boxes' faces in the shared plane are found, nothing else.
#include <polyloc/map/coincident_faces.hpp>
#include <polyloc/raycast/factory.hpp>

#include <gtest/gtest.h>

#include <string>
#include <vector>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_coincident_faces {

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


Mesh touchingBoxes(const Eigen::Vector3d& shift) {
  Mesh m;
  m.addBox(shift + Eigen::Vector3d(0, 0, 0), shift + Eigen::Vector3d(1, 1, 1), 1);
  m.addBox(shift + Eigen::Vector3d(1, 0.25, 0), shift + Eigen::Vector3d(2, 0.75, 0.5), 2);
  return m;
}


// Was: a 1e-5 m tolerance at any scale; at x = 5e5 m floats are 3 cm apart, hit points fell off
// the covered boxes and the tie rule was skipped without a word.
TEST(CoincidentFaces, FarFromTheOriginTheToleranceGrowsWithTheCoordinates) {
  const Eigen::Vector3d shift(500000.1, 0.2, 0);
  const Mesh m = touchingBoxes(shift);
  const CoincidentFaces c(m);
  EXPECT_EQ(c.triangles(), 4u);
  EXPECT_FLOAT_EQ(c.tolerance(), 0.03125f);  // a float step at 5e5
  EXPECT_FLOAT_EQ(CoincidentFaces(touchingBoxes(Eigen::Vector3d::Zero())).tolerance(), 1e-5f);  // near the origin: as given
  // A hit point computed along a ray lands a float step or two off the face.
  bool covered = false;
  for (uint32_t t = 0; t < 12; ++t) covered = covered || c.covers(t, (shift + Eigen::Vector3d(1.03, 0.5, 0.25)).cast<float>());
  EXPECT_TRUE(covered);
}

// The tie rule's answer (a ray from inside the first box, through the face the second stands
// against: the back face wins) does not depend on where the building stands.
TEST(CoincidentFaces, TheTieRuleHoldsInUtmCoordinatesOnEveryExactBackend) {
  std::vector<std::string> names{"embree"};
#ifdef POLYLOC_HAVE_GPU
  names.push_back("gpu");
#endif
  for (const Eigen::Vector3d& shift : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(500000.1, 0.2, 0)}) {
    const Mesh m = touchingBoxes(shift);
    std::vector<float> ox, oy, oz, dx, dy, dz;
    for (float y : {0.3f, 0.4f, 0.5f, 0.6f, 0.7f})
      for (float z : {0.1f, 0.25f, 0.4f})
        for (float x : {0.25f, 0.5f, 0.75f}) {
          ox.push_back(float(shift.x() + x)), oy.push_back(float(shift.y() + y)), oz.push_back(float(shift.z() + z));
          dx.push_back(1), dy.push_back(0), dz.push_back(0);
        }
    const size_t n = ox.size();
    for (const std::string& name : names) {
      const auto caster = makeCaster(name, m);
      std::vector<float> range(n, -1);
      std::vector<uint32_t> label(n, 99);
      caster->castRays({ox.data(), oy.data(), oz.data(), dx.data(), dy.data(), dz.data(), nullptr, nullptr, n},
                       {range.data(), nullptr, label.data()});
      for (size_t i = 0; i < n; ++i) {
        EXPECT_EQ(label[i], 1u) << name << " shift " << shift.x() << " ray " << i;
        EXPECT_EQ(range[i], 0.f) << name << " shift " << shift.x() << " ray " << i;  // inside a solid: the window start
      }
    }
  }
}

}  // namespace polyloc::t_coincident_faces
