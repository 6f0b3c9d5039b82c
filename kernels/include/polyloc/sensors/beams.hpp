// Beam directions of one sensor in its own frame (x forward, y left, z up; REP-103), as
// structure-of-arrays unit vectors, with the sensor's range limits. Every sensor model produces
// one; ray casters take it as is.
#pragma once

#include <cstddef>
#include <vector>

namespace polyloc {

struct BeamSet {
  std::vector<float> dx, dy, dz;  // unit directions, sensor frame
  float range_min = 0.f;          // metres; returns closer than this are invalid
  float range_max = 30.f;         // metres; nothing is seen beyond

  size_t size() const { return dx.size(); }
  void push(float x, float y, float z) {
    dx.push_back(x);
    dy.push_back(y);
    dz.push_back(z);
  }
};

}  // namespace polyloc
