#include <polyloc/tracking/config_yaml.hpp>
#include <polyloc/tracking/people_tracker.hpp>

#include <stdexcept>

namespace polyloc {
namespace {

void parseMotion(ConfigMap m, MotionConfig& c) {
  c.margin = m.getDouble("margin", c.margin, 0, 10);
  c.margin_per_m = m.getDouble("margin_per_m", c.margin_per_m, 0, 1);
  c.min_range = m.getDouble("min_range", c.min_range, 0, 1000);
  c.max_range = m.getDouble("max_range", c.max_range, 0.1, 1000);
  if (c.max_range <= c.min_range) m.value("max_range").fail("must be > min_range");
  if (m.has("reference_ages")) {
    const ConfigValue v = m.value("reference_ages");
    c.reference_ages = v.asDoubles();
    if (c.reference_ages.empty() || c.reference_ages.size() > 32) v.fail("must list 1 to 32 ages (s)");
    for (double a : c.reference_ages)
      if (!(a > 0 && a <= 60)) v.fail("ages must be in (0, 60] s");
  }
  c.max_speed = m.getDouble("max_speed", c.max_speed, 0, 100);
  c.recede_max = m.getDouble("recede_max", c.recede_max, 0, 100);
  c.static_time = m.getDouble("static_time", c.static_time, 0, 3600);
  c.static_gap = m.getDouble("static_gap", c.static_gap, 0, 3600);
  c.static_cell = m.getDouble("static_cell", c.static_cell, 0.01, 10);
  c.grow_distance = m.getDouble("grow_distance", c.grow_distance, 0, 10);
  c.turn_margin = m.getDouble("turn_margin", c.turn_margin, 0, 10);
  c.travel_margin = m.getDouble("travel_margin", c.travel_margin, 0, 10);
  c.window_beams = int(m.getCount("window_beams", size_t(c.window_beams), 0, 50));
  c.jump_distance = m.getDouble("jump_distance", c.jump_distance, 0, 1000);
  c.jump_angle = m.getAngle("jump_angle", c.jump_angle);
  c.max_moved_fraction = m.getDouble("max_moved_fraction", c.max_moved_fraction, 0, 1);
  m.finish();
}

void parseCluster(ConfigMap m, ClusterConfig& c) {
  c.distance = m.getDouble("distance", c.distance, 1e-3, 10);
  c.min_points = m.getCount("min_points", c.min_points, 1, 100000);
  c.max_extent = m.getDouble("max_extent", c.max_extent, 1e-3, 100);
  c.surface_offset = m.getDouble("surface_offset", c.surface_offset, -1, 1);
  c.min_sigma = m.getDouble("min_sigma", c.min_sigma, 0, 10);
  m.finish();
}

void parseTracker(ConfigMap m, TrackerConfig& c) {
  c.acceleration_sigma = m.getDouble("acceleration_sigma", c.acceleration_sigma, 0, 100);
  c.measurement_sigma = m.getDouble("measurement_sigma", c.measurement_sigma, 1e-4, 10);
  c.gate = m.getDouble("gate", c.gate, 0.1, 100);
  c.confirm_hits = int(m.getCount("confirm_hits", size_t(c.confirm_hits), 1, 1000));
  c.confirm_time = m.getDouble("confirm_time", c.confirm_time, 0, 3600);
  c.confirm_distance = m.getDouble("confirm_distance", c.confirm_distance, 0, 100);
  c.timeout = m.getDouble("timeout", c.timeout, 0, 3600);
  c.empty_timeout = m.getDouble("empty_timeout", c.empty_timeout, 0, 3600);
  c.empty_radius = m.getDouble("empty_radius", c.empty_radius, 0, 10);
  c.max_sigma = m.getDouble("max_sigma", c.max_sigma, 1e-3, 100);
  c.init_speed_sigma = m.getDouble("init_speed_sigma", c.init_speed_sigma, 0, 100);
  c.max_speed = m.getDouble("max_speed", c.max_speed, 0, 100);
  c.new_track_distance = m.getDouble("new_track_distance", c.new_track_distance, 0, 100);
  c.revive_time = m.getDouble("revive_time", c.revive_time, 0, 3600);
  c.revive_distance = m.getDouble("revive_distance", c.revive_distance, 0, 100);
  c.revive_speed = m.getDouble("revive_speed", c.revive_speed, 0, 100);
  m.finish();
}

}  // namespace

TrackingConfig parseTrackingConfig(ConfigMap m, const Rig* rig) {
  TrackingConfig c;
  if (m.has("sensors")) {
    const ConfigValue v = m.value("sensors");
    if (!v.isSequence()) v.fail("expected a list of sensor names");
    for (const ConfigValue& item : v.items()) c.sensors.push_back(item.asString());
    if (rig) {
      try {
        trackingSensors(*rig, c);
      } catch (const std::invalid_argument& e) {
        v.fail(e.what());
      }
    }
  }
  c.sync_tolerance = m.getDouble("sync_tolerance", c.sync_tolerance, 0, 10);
  if (m.has("motion")) parseMotion(m.map("motion"), c.motion);
  if (m.has("cluster")) parseCluster(m.map("cluster"), c.cluster);
  if (m.has("tracker")) parseTracker(m.map("tracker"), c.tracker);
  m.finish();
  return c;
}

}  // namespace polyloc
