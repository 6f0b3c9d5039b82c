// DistanceField3D: known distances in the box room, clamping, outside the grid, and the
// documented error bound against brute-force closest-point distances.
#include "mcl_fixtures.hpp"

#include <polyloc/geometry/closest_point.hpp>
#include <polyloc/map/distance_field.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_distance_field {

using namespace polyloc;
using namespace polyloc::test;


// Brute force: the distance to the nearest triangle, clamped as the field clamps.
float exactDistance(const Mesh& m, const Eigen::Vector3f& p, float max_distance) {
  float best = std::numeric_limits<float>::infinity();
  for (const Triangle& t : m.triangles)
    best = std::min(best, (p - closestPointOnTriangle(p, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]])).norm());
  return std::min(best, max_distance);
}

DistanceFieldConfig config(double res, double max_d) {
  DistanceFieldConfig c;
  c.resolution = res;
  c.max_distance = max_d;
  c.padding = max_d;
  return c;
}

struct ErrorStats {
  float worst = 0, worst_far = 0;  // far: more than one voxel from every surface
  size_t below = 0;                // points where the field reads less than the truth by > 1 mm
};

// Random points over the mesh bounds (plus a little), field vs brute force.
ErrorStats compare(const Mesh& m, const DistanceField3D& f, size_t n, uint64_t seed) {
  const Eigen::AlignedBox3f b = m.bounds();
  const CounterRng rng(seed);
  ErrorStats s;
  for (size_t i = 0; i < n; ++i) {
    Eigen::Vector3f p;
    for (int a = 0; a < 3; ++a)
      p[a] = b.min()[a] - 0.3f + float(rng.uniform(i, uint64_t(a))) * (b.max()[a] - b.min()[a] + 0.6f);
    const float truth = exactDistance(m, p, f.maxDistance()), got = f.distance(p);
    const float err = std::abs(got - truth);
    s.worst = std::max(s.worst, err);
    if (truth > f.resolution()) s.worst_far = std::max(s.worst_far, err);
    if (got < truth - 1e-3f) ++s.below;
  }
  return s;
}


TEST(DistanceField, KnownDistancesInTheBoxRoom) {
  const Mesh room = boxRoom(4.f, 3.f, 2.5f, 0.2f);  // interior [-4,4] x [-3,3] x [0,2.5]
  const DistanceField3D f(room, config(0.05, 2.0));
  // Centre: floor and ceiling 1.25 m away, walls 3 and 4 m.
  EXPECT_NEAR(f.distance({0, 0, 1.25f}), 1.25f, 1e-3);
  // In front of one wall only (the field is linear there: no interpolation error).
  EXPECT_NEAR(f.distance({3.9f, 0.3f, 1.2f}), 0.1f, 1e-3);
  EXPECT_NEAR(f.distance({-3.63f, 0.1f, 1.1f}), 0.37f, 1e-3);
  EXPECT_NEAR(f.distance({0.2f, 0.1f, 0.42f}), 0.42f, 1e-3);  // above the floor
  // Inside the wall slab (4 .. 4.2): 0.1 to either face.
  EXPECT_NEAR(f.distance({4.1f, 0.5f, 1.0f}), 0.1f, 1e-3);
  // Outside the room, off the outer vertical edge of a corner post at (4.2, 3.2): 0.5 m.
  EXPECT_NEAR(f.distance({4.5f, 3.6f, 1.0f}), 0.5f, 0.01);
  // On a surface the reading is at most half a voxel (the |d| kink smoothed by interpolation).
  EXPECT_LE(f.distance({4.0f, 0.12f, 1.03f}), 0.5f * 0.05f + 1e-3f);
}

TEST(DistanceField, ClampsAndOutsideTheGridIsFar) {
  const Mesh room = boxRoom(4.f, 3.f, 2.5f, 0.2f);
  const DistanceField3D f(room, config(0.05, 1.0));
  EXPECT_FLOAT_EQ(f.maxDistance(), 1.0f);
  EXPECT_NEAR(f.distance({0, 0, 1.25f}), 1.0f, 1e-4);  // 1.25 m, clamped
  EXPECT_NEAR(f.distance({1, -0.5f, 1.1f}), 1.0f, 1e-4);
  EXPECT_EQ(f.distance({100.f, 0, 1}), 1.0f);
  EXPECT_EQ(f.distance({0, 0, -50.f}), 1.0f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(f.distance({nan, 0, 1}), 1.0f);
  // Just inside the padded grid, above the ceiling slab (top at 2.7): 0.5 m from it.
  EXPECT_NEAR(f.distance({0, 0, 3.2f}), 0.5f, 1e-3);
  // Grid: bounds + padding on every side, 2 bytes a node.
  EXPECT_EQ(f.numNodes(), f.nx() * f.ny() * f.nz());
  EXPECT_EQ(f.memoryBytes(), 2 * f.numNodes());
  EXPECT_LE(f.origin().x(), -4.2f - 1.0f + 1e-4f);
  EXPECT_GE(f.origin().x() + f.resolution() * float(f.nx() - 1), 4.2f + 1.0f - 1e-4f);
  EXPECT_GE(f.origin().z() + f.resolution() * float(f.nz() - 1), 2.7f + 1.0f - 1e-4f);
}

TEST(DistanceField, ErrorWithinTheDocumentedBound) {
  const Mesh m = asymmetricRoom();
  const double h = 0.05;
  const DistanceField3D f(m, config(h, 1.0));
  const ErrorStats s = compare(m, f, 400, 7);
  std::printf("[distance field] asymmetric room: worst err %.4f m, worst far (> h) %.4f m\n", s.worst, s.worst_far);
  EXPECT_LE(s.worst, 0.87 * h);     // trilinear of a 1-Lipschitz function: mean distance to corners
  EXPECT_LE(s.worst_far, 0.5 * h);  // far from surfaces: half a voxel
  // Node values are exact near surfaces and never below the truth elsewhere.
  const CounterRng rng(3);
  for (size_t n = 0; n < 2000; ++n) {
    const size_t i = size_t(rng.uniform(n, 0) * double(f.nx())), j = size_t(rng.uniform(n, 1) * double(f.ny())),
                 k = size_t(rng.uniform(n, 2) * double(f.nz()));
    const float truth = exactDistance(m, f.nodePosition(i, j, k), 1.0f), got = f.nodeDistance(i, j, k);
    if (truth < 2 * h) {
      EXPECT_NEAR(got, truth, 1e-4) << i << " " << j << " " << k;
    }
    EXPECT_GE(got, truth - 1e-4f) << i << " " << j << " " << k;
    EXPECT_LE(got, truth + h) << i << " " << j << " " << k;
  }
}

TEST(DistanceField, ObliqueSurfacesStayWithinTheBound) {
  // The room rotated 30 deg about z and tilted 10 deg: no face is aligned with the grid.
  Mesh m = asymmetricRoom();
  const Eigen::Matrix3f R = (Eigen::AngleAxisf(0.52f, Eigen::Vector3f::UnitZ()) *
                             Eigen::AngleAxisf(0.17f, Eigen::Vector3f::UnitX())).toRotationMatrix();
  for (auto& v : m.vertices) v = R * v;
  const double h = 0.05;
  const DistanceField3D f(m, config(h, 1.0));
  const ErrorStats s = compare(m, f, 400, 11);
  std::printf("[distance field] oblique room: worst err %.4f m, worst far (> h) %.4f m\n", s.worst, s.worst_far);
  EXPECT_LE(s.worst, 0.87 * h);
  EXPECT_LE(s.worst_far, 0.5 * h);
}

TEST(DistanceField, BatchQueryMatchesSingleQueries) {
  const Mesh m = asymmetricRoom();
  const DistanceField3D f(m, config(0.1, 1.0));
  std::vector<float> x, y, z, out(50);
  for (int i = 0; i < 50; ++i) x.push_back(-5.f + 0.2f * float(i)), y.push_back(0.05f * float(i) - 1), z.push_back(0.3f);
  f.distances(x.data(), y.data(), z.data(), x.size(), out.data());
  for (size_t i = 0; i < x.size(); ++i) EXPECT_EQ(out[i], f.distance({x[i], y[i], z[i]})) << i;
}

TEST(DistanceField, EmptyMeshAndBadConfig) {
  const DistanceField3D empty(Mesh{}, config(0.05, 0.8));
  EXPECT_EQ(empty.numNodes(), 0u);
  EXPECT_FLOAT_EQ(empty.distance({0, 0, 0}), 0.8f);
  const Mesh room = boxRoom(1.f, 1.f, 1.f, 0.1f);
  EXPECT_THROW((DistanceField3D{room, config(0.0, 1.0)}), std::invalid_argument);
  EXPECT_THROW((DistanceField3D{room, config(0.05, -1.0)}), std::invalid_argument);
  DistanceFieldConfig c = config(0.05, 1.0);
  c.padding = -0.1;
  EXPECT_THROW((DistanceField3D{room, c}), std::invalid_argument);
  c = config(1e-4, 1.0);  // 30000^3 nodes
  EXPECT_THROW((DistanceField3D{room, c}), std::invalid_argument);
}

}  // namespace polyloc::t_distance_field
