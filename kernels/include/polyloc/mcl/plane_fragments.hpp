// Plane-fragment measurement model (after a 2008 thesis on a robot with one horizontal and
// several tilted 2D scanners). Line segments are fitted per scan (line_segments.hpp); segments
// of two scanners with different scan planes whose lines cross give a plane fragment: a point
// on a surface and the surface normal, spanned by the two segment directions. A particle is
// weighed by casting a ray from the sensor towards each fragment point and comparing the first
// hit with the fragment: distance along the ray and normal (sign-agnostic).
//
// The scanners do not scan at the same instant: the model keeps each scanner's latest segments
// in the base frame with the odometry at its stamp, and moves them into the current base frame
// by the odometry difference when another scanner's frame arrives (max_age bounds the drift).
// Frames of other sensor kinds (lidar, depth camera) go to an internal beam model.
#pragma once

#include <polyloc/mcl/beam_model.hpp>
#include <polyloc/mcl/line_segments.hpp>
#include <polyloc/mcl/sensor_model.hpp>

#include <Eigen/Core>
#include <span>
#include <vector>

namespace polyloc {

struct PlaneFragment {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   // base frame
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ(); // unit, sign arbitrary
  size_t sensor = 0;                                 // rig sensor to cast the ray from
};

struct FragmentParams {
  double intersect_tolerance = 0.05;  // m
  double extent_margin = 0.1;         // m
  double min_angle = 0.349065850398866;  // rad
};

// Moves a segment by a rigid transform (e.g. base_T_sensor).
LineSegment transformSegment(const Pose& T, const LineSegment& s);

// Fragments from segments a (scan plane normal na) and b (normal nb), all in one frame. A pair
// gives one when its lines pass within intersect_tolerance, the closest points lie within both
// segments (plus extent_margin), the lines cross at more than min_angle, and the normal is at
// least min_angle away from both scan-plane normals (two lines of one plane span that plane,
// not a surface).
std::vector<PlaneFragment> buildFragments(std::span<const LineSegment> a, const Eigen::Vector3d& na,
                                          std::span<const LineSegment> b, const Eigen::Vector3d& nb,
                                          size_t cast_sensor, const FragmentParams& params = {});

class PlaneFragmentModel : public SensorModel {
 public:
  // Throws std::invalid_argument when the rig has fewer than two planar scanners.
  PlaneFragmentModel(const RayCaster& caster, const Rig& rig, const MclConfig& config);
  const char* name() const override { return "plane_fragments"; }
  size_t weigh(const ParticleSet& particles, const SensorFrame& frame, std::span<double> loglik) override;
  double unexplainedLogLikelihood(size_t sensor) const override;
  double logScale() const override { return config_.plane_fragments.log_scale; }

  // The fragments of a frame (fits the frame's segments and stores them, as weigh does).
  const std::vector<PlaneFragment>& fragments(const SensorFrame& frame);
  // log p(fragment | first hit): range/normal of the hit (+inf: none in the window).
  double logLikelihood(double expected, float range, const Eigen::Vector3d& normal,
                       const Eigen::Vector3d& hit_normal) const;

 private:
  struct Latest {  // the newest segments of one planar scanner
    bool valid = false;
    int64_t stamp_ns = 0;
    Pose odom_T_base;
    std::vector<LineSegment> segments;  // base frame at stamp_ns
  };
  double floorDensity() const;

  const RayCaster& caster_;
  const Rig& rig_;
  const MclConfig& config_;
  BeamSensorModel beam_;
  std::vector<BeamSet> beams_;
  std::vector<uint8_t> planar_;
  std::vector<Latest> latest_;
  std::vector<PlaneFragment> frags_;
  // Reused between calls: rays and hits, particle-major (p * F + f).
  std::vector<float> ox_, oy_, oz_, dx_, dy_, dz_, tmin_, tmax_, range_, nx_, ny_, nz_;
};

}  // namespace polyloc
