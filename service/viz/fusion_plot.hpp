// The picture of `polyloc map fuse`: the fused mesh seen along the data set's z (x right, y up)
// and along its y (x right, z up), its surface shaded by how much of it lies behind each pixel,
// with the camera's path (blue) and a title.
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/map/mesh.hpp>

#include <string>
#include <vector>

namespace polyloc::viz {

// Throws std::runtime_error naming the file when it cannot be written.
void drawFusion(const Mesh& mesh, const std::vector<Pose>& path, const std::string& title, const std::string& png);

}  // namespace polyloc::viz
