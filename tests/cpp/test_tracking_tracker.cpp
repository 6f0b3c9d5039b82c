// The multi-target tracker: confirmation after N hits, drop after the timeout or sooner when the
// place is seen empty, crossing targets keep their ids, the
// uncertainty-ellipse query for the obstacle memory, and bad input.
#include <polyloc/tracking/tracker.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <optional>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_tracking_tracker {

using namespace polyloc;


constexpr int64_t kStep = 80'000'000;  // 12.5 Hz

Detection at(double x, double y, int64_t stamp) {
  Detection d;
  d.stamp_ns = stamp;
  d.position = {x, y};
  d.covariance = Eigen::Matrix2d::Identity() * 0.01;
  d.points = 10;
  return d;
}

std::optional<TrackState> find(const Tracks& t, uint32_t id) {
  for (const TrackState& s : t.items)
    if (s.id == id) return s;
  return std::nullopt;
}


TEST(TrackingTracker, ConfirmedAfterNHitsDroppedAfterTimeout) {
  TrackerConfig c;
  c.confirm_hits = 3;
  c.confirm_distance = 0;
  c.timeout = 0.5;
  MultiTargetTracker tracker(c);
  for (int k = 0; k < 3; ++k) {
    const Detection d = at(0.1 * k, 0, k * kStep);  // walking at 1.25 m/s
    tracker.update(k * kStep, std::span(&d, 1));
    ASSERT_EQ(tracker.tracks().items.size(), 1u);
    EXPECT_EQ(tracker.tracks().items[0].status, k < 2 ? TrackStatus::Tentative : TrackStatus::Confirmed) << k;
    EXPECT_EQ(tracker.tracks().items[0].hits, uint32_t(k + 1));
  }
  const uint32_t id = tracker.tracks().items[0].id;
  // No detections: kept while within the timeout, then reported once as deleted, then gone.
  int k = 3;
  for (; k * kStep - 2 * kStep <= int64_t(0.5e9); ++k) {
    tracker.update(k * kStep, {});
    ASSERT_TRUE(find(tracker.tracks(), id)) << k;
    EXPECT_EQ(find(tracker.tracks(), id)->status, TrackStatus::Confirmed);
  }
  tracker.update(k * kStep, {});
  ASSERT_TRUE(find(tracker.tracks(), id));
  EXPECT_EQ(find(tracker.tracks(), id)->status, TrackStatus::Deleted);
  tracker.update((k + 1) * kStep, {});
  EXPECT_FALSE(find(tracker.tracks(), id));
}

TEST(TrackingTracker, SpotThatDoesNotMoveIsNeverConfirmed) {
  TrackerConfig c;  // confirm_distance 0.3 m
  MultiTargetTracker tracker(c);
  for (int k = 0; k < 20; ++k) {  // a flickering surface: detections on one spot
    const Detection d = at(2.0 + 0.03 * std::sin(k), 1.0, k * kStep);
    tracker.update(k * kStep, std::span(&d, 1));
    EXPECT_EQ(tracker.tracks().confirmed(), 0u);
  }
}

TEST(TrackingTracker, UncertaintyPastMaxSigmaDrops) {
  TrackerConfig c;
  c.confirm_distance = 0;
  c.timeout = 100;        // only the covariance ends it
  c.max_sigma = 0.3;
  MultiTargetTracker tracker(c);
  for (int k = 0; k < 5; ++k) {
    const Detection d = at(0.1 * k, 0, k * kStep);
    tracker.update(k * kStep, std::span(&d, 1));
  }
  int k = 5;
  while (tracker.tracks().confirmed() == 1 && k < 200) tracker.update(k++ * kStep, {});
  EXPECT_LT(k, 200);
  const TrackState& last = tracker.tracks().items.at(0);
  EXPECT_EQ(last.status, TrackStatus::Deleted);
  EXPECT_GT(last.ellipse.major, 0.3);
}

TEST(TrackingTracker, EmptyPlaceDropsSooner) {
  TrackerConfig c;
  c.confirm_distance = 0;
  c.timeout = 0.5, c.empty_timeout = 0.2;
  auto lifetime = [&](Visibility v) {
    MultiTargetTracker tracker(c);
    for (int k = 0; k < 4; ++k) {
      const Detection d = at(0.1 * k, 0, k * kStep);
      tracker.update(k * kStep, std::span(&d, 1));
    }
    int k = 4;
    for (; tracker.tracks().confirmed() == 1 && k < 100; ++k)
      tracker.update(k * kStep, {}, [v](const Eigen::Vector2d&) { return v; });
    return double(k - 4) * 0.08;
  };
  EXPECT_NEAR(lifetime(Visibility::Unknown), 0.56, 0.09);
  EXPECT_NEAR(lifetime(Visibility::Occupied), 0.56, 0.09);
  EXPECT_NEAR(lifetime(Visibility::Empty), 0.24, 0.09);
  EXPECT_NEAR(lifetime(Visibility::Hidden), 0.56, 0.09);
}

TEST(TrackingTracker, CrossingTargetsKeepTheirIds) {
  MultiTargetTracker tracker;
  std::optional<uint32_t> id_a, id_b;
  for (int k = 0; k <= 75; ++k) {  // 6 s at 1 m/s each, crossing at 60 deg in the middle
    const double t = k * 0.08;
    const Eigen::Vector2d a(-3 + t, -1.5 + 0.5 * t), b(-3 + t, 1.5 - 0.5 * t);
    // Small alternating offsets like a gait; at the crossing the two merge into one detection.
    const double wob = 0.04 * ((k % 2) ? 1 : -1);
    std::vector<Detection> d;
    if ((a - b).norm() < 0.4) d = {at(0.5 * (a + b).x(), 0.5 * (a + b).y(), 0)};
    else d = {at(a.x() + wob, a.y(), 0), at(b.x() - wob, b.y(), 0)};
    tracker.update(k * kStep, d);
    if (t < 1.0) continue;
    ASSERT_EQ(tracker.tracks().confirmed(), 2u) << "t = " << t;
    for (const TrackState& s : tracker.tracks().items) {
      const bool is_a = (s.position - a).norm() < (s.position - b).norm();
      std::optional<uint32_t>& id = is_a ? id_a : id_b;
      if ((a - b).norm() < 0.6) continue;  // too close to tell which is which
      if (!id) id = s.id;
      EXPECT_EQ(*id, s.id) << (is_a ? "a" : "b") << " at t = " << t;
    }
  }
  ASSERT_TRUE(id_a && id_b);
  EXPECT_NE(*id_a, *id_b);
}

TEST(TrackingTracker, InsideTestsConfirmedEllipses) {
  Tracks t;
  TrackState s;
  s.status = TrackStatus::Confirmed;
  s.position = {1, 1};
  s.position_cov << 0.04, 0, 0, 0.01;  // 0.2 m along x, 0.1 m along y
  t.items.push_back(s);
  s.status = TrackStatus::Tentative;
  s.position = {5, 5};
  t.items.push_back(s);
  EXPECT_TRUE(t.inside({1, 1}, 2));
  EXPECT_TRUE(t.inside({1.39, 1}, 2));   // 0.39 < 2 * 0.2
  EXPECT_FALSE(t.inside({1, 1.21}, 2));  // 0.21 > 2 * 0.1
  EXPECT_TRUE(t.inside({1, 1.21}, 2, 0.3));  // grown by a body radius
  EXPECT_FALSE(t.inside({5, 5}, 3));     // tentative tracks do not count
  EXPECT_FALSE(t.inside({std::nan(""), 1}, 2));
  EXPECT_EQ(t.confirmed(), 1u);
}

TEST(TrackingTracker, BadDetectionsAndStampsAreIgnored) {
  MultiTargetTracker tracker;
  std::vector<Detection> d = {at(std::nan(""), 0, 0), at(1, 1, 0)};
  EXPECT_TRUE(tracker.update(kStep, d));
  EXPECT_EQ(tracker.tracks().items.size(), 1u);
  EXPECT_FALSE(tracker.update(0, d));  // before the last update
  EXPECT_TRUE(tracker.update(2 * kStep, {}));
  const Tracks later = tracker.predicted(10 * kStep);
  EXPECT_EQ(later.items.size(), 1u);
  EXPECT_EQ(later.stamp_ns, 10 * kStep);
}

TEST(TrackingTracker, PersonBackFromHidingKeepsTheirId) {
  TrackerConfig c;
  c.confirm_distance = 0;
  c.timeout = 0.5;
  // Walks at 1.25 m/s along x; hidden from 1.6 s to 4.0 s (its track is dropped), then seen
  // again where it walked on to, and somebody else appears far off at the same time.
  auto run = [&](const TrackerConfig& cfg, uint32_t& first_id, uint32_t& back_id, uint32_t& other_id) {
    MultiTargetTracker tracker(cfg);
    for (int k = 0; k <= 70; ++k) {
      const int64_t t = k * kStep;
      const double x = 0.1 * k;
      std::vector<Detection> d;
      if (k < 20 || k >= 50) d.push_back(at(x, 0, t));
      if (k >= 50) d.push_back(at(x - 4.0, 3.0, t));
      tracker.update(t, d);
      for (const TrackState& s : tracker.tracks().items) {
        if (s.status != TrackStatus::Confirmed) continue;
        if (k == 10) first_id = s.id;
        if (k == 70 && s.position.y() < 1) back_id = s.id;
        if (k == 70 && s.position.y() > 1) other_id = s.id;
      }
    }
  };
  uint32_t a = 0, b = 0, o = 0;
  run(c, a, b, o);
  EXPECT_NE(a, 0u);
  EXPECT_EQ(b, a);  // revived: within revive_distance + revive_speed x 2.4 s of where it walked to
  EXPECT_NE(o, a);  // the stranger 4 m away gets an id of their own
  EXPECT_NE(o, 0u);
  c.revive_time = 0;  // off: a new id
  run(c, a, b, o);
  EXPECT_NE(b, a);
}

}  // namespace polyloc::t_tracking_tracker
