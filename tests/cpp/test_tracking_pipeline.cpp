// The tracking pipeline end to end on analytic scans of one level scanner: two boxes walking
// across each other's path keep their track ids; with a second scanner at the same stamps each
// box is still one track.
#include "tracking_fixtures.hpp"

#include <polyloc/tracking/people_tracker.hpp>

#include <gtest/gtest.h>

#include <map>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_tracking_pipeline {

using namespace polyloc;
using test::kTestStep;
using test::Scene2D;


Rig scannerRig(int scanners) {
  Rig rig;
  rig.name = "test";
  rig.add(Sensor{"front", sickS300(), Pose::fromXYZRPY(0.3, 0, 0.1, 0, 0, 0)}, "sick_s300");
  if (scanners > 1) rig.add(Sensor{"left", sickS300(), Pose::fromXYZRPY(0, 0.3, 0.1, 0, 0, M_PI / 2)}, "sick_s300");
  return rig;
}

// Box a walks north-east, box b south-east at 1 m/s, crossing the same point 1.5 s apart:
// 0.9 m apart at the closest (closer than cluster.distance they would merge into one detection).
std::pair<Eigen::Vector2d, Eigen::Vector2d> boxes(double t) {
  const Eigen::Vector2d a = Eigen::Vector2d(0.0, -2.0) + t * Eigen::Vector2d(0.6, 0.8);
  const Eigen::Vector2d b = Eigen::Vector2d(0.9, 2.56) + t * Eigen::Vector2d(0.6, -0.8);
  return {a, b};
}

void runCrossing(int scanners) {
  const Rig rig = scannerRig(scanners);
  PeopleTracker people(rig, TrackingConfig{});
  const Scene2D room = Scene2D::room(6, 4);
  const Pose base = Pose::planar(-4.0, 0.0, 0.0);
  std::map<char, uint32_t> ids;
  for (int k = 0; k < 70; ++k) {
    const double t = k * 0.08;
    const auto [a, b] = boxes(t);
    const Scene2D scene = room.with(a, 0.12).with(b, 0.12);
    for (size_t s = 0; s < rig.size(); ++s) {
      const Pose p = base * rig.sensors[s].mount;
      ASSERT_EQ(people.addScan(s, k * kTestStep, p, test::scan2d(sickS300(), p, scene)), ScanCheck::Ok);
    }
    people.flush();
    if (t < 1.5) continue;  // references fill up, tracks confirm
    ASSERT_EQ(people.tracks().confirmed(), 2u) << "t = " << t;
    for (const TrackState& tr : people.tracks().items) {
      if (tr.status != TrackStatus::Confirmed) continue;
      const char which = (tr.position - a).norm() < (tr.position - b).norm() ? 'a' : 'b';
      EXPECT_LT((tr.position - (which == 'a' ? a : b)).norm(), 0.25) << which << " at t = " << t;
      const auto [it, fresh] = ids.try_emplace(which, tr.id);
      EXPECT_EQ(it->second, tr.id) << which << " changed its id at t = " << t;
    }
  }
  ASSERT_EQ(ids.size(), 2u);
  EXPECT_NE(ids['a'], ids['b']);
  EXPECT_EQ(people.counters().steps, 70u);
  EXPECT_EQ(people.counters().scans, 70u * rig.size());
}


TEST(TrackingPipeline, CrossingBoxesKeepTheirIds) { runCrossing(1); }

TEST(TrackingPipeline, TwoScannersOneTrackPerBox) { runCrossing(2); }

}  // namespace polyloc::t_tracking_pipeline
