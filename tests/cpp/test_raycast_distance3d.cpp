// distance3d backend, beyond the contract of every caster (test_raycast_conformance.cpp): the
// inside marks of the unsigned field and clearance from them.
#include <polyloc/raycast/distance3d.hpp>

#include "fixtures.hpp"
#include "raycast_helpers.hpp"

#include <gtest/gtest.h>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_raycast_distance3d {

using namespace polyloc;
using polyloc::test::freeAt;


Distance3dOptions roomOptions() {
  Distance3dOptions o;
  o.field.resolution = 0.05;
  return o;
}

// Interior [-2, 2] x [-1.5, 1.5] x [0, 3]; walls 0.2 m thick; nodes 5 cm apart.
struct Distance3dRoom : ::testing::Test {
  Mesh mesh = polyloc::test::boxRoom(2.f, 1.5f, 3.f, 0.2f);
  Distance3dCaster caster{mesh, roomOptions()};
};


TEST_F(Distance3dRoom, InsideMarksAndClearance) {
  EXPECT_TRUE(caster.inside({2.1f, 0, 1}));
  EXPECT_TRUE(caster.inside({0, 0, -0.1f}));  // floor slab
  EXPECT_FALSE(caster.inside({0, 0, 1}));
  EXPECT_FALSE(caster.inside({3, 0, 1}));  // outside the building
  EXPECT_FALSE(freeAt(caster, {2.1f, 0, 1}, 0.f));
  EXPECT_TRUE(freeAt(caster, {0, 0, 1}, 0.9f));
  EXPECT_FALSE(freeAt(caster, {1.8f, 0, 1}, 0.3f));
  EXPECT_TRUE(freeAt(caster, {1.6f, 0, 1}, 0.3f));
}

}  // namespace polyloc::t_raycast_distance3d
