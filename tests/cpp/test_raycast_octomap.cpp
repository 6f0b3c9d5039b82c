// octomap backend, beyond the contract of every caster (test_raycast_conformance.cpp): occupied
// surface voxels, unknown interiors, clearance.
#include <polyloc/raycast/octomap.hpp>

#include "fixtures.hpp"
#include "raycast_helpers.hpp"

#include <gtest/gtest.h>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_raycast_octomap {

using namespace polyloc;
using polyloc::test::freeAt;


struct OctomapRoom : ::testing::Test {
  Mesh mesh = polyloc::test::boxRoom(2.f, 1.5f, 3.f, 0.2f);
  OctomapCaster caster{mesh, OctomapOptions{}};
};


TEST_F(OctomapRoom, SurfaceVoxelsAndClearance) {
  EXPECT_TRUE(caster.occupied({2.0f + 0.01f, 0, 1}) || caster.occupied({2.0f - 0.01f, 0, 1}));
  EXPECT_FALSE(caster.occupied({0, 0, 1}));
  EXPECT_GT(caster.occupiedVoxels(), 1000u);
  EXPECT_TRUE(freeAt(caster, {0, 0, 1}, 0.5f));
  EXPECT_FALSE(freeAt(caster, {1.8f, 0, 1}, 0.3f));
  EXPECT_TRUE(freeAt(caster, {1.6f, 0, 1}, 0.3f));
  EXPECT_FALSE(freeAt(caster, {2.0f, 0, 1}, 0.f));  // on the wall surface
}

}  // namespace polyloc::t_raycast_octomap
