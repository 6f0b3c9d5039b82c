// Internal to the simulator: one mounted sensor's frames, from beams to messages. Tracing
// (static map in one batch, people per frame, glass passed or mirrored in further batches),
// then noise and artefacts (noise.hpp), then the ROS 2 messages of the sensor's kind.
#pragma once

#include <polyloc/io/recording.hpp>
#include <polyloc/raycast/ray_caster.hpp>
#include <polyloc/sim/noise.hpp>
#include <polyloc/sim/people.hpp>
#include <polyloc/sim/simulator.hpp>

#include <string>
#include <vector>

namespace polyloc::detail {

// Random stream of one sensor frame: draws of beam b are rng(seed).xxx(stream, b, k).
inline uint64_t frameStream(size_t sensor, uint64_t frame) { return (uint64_t(sensor + 1) << 40) ^ frame; }
// Draws fixed for the whole run (per-beam bias): a frame index no run reaches.
inline uint64_t sensorStream(size_t sensor) { return frameStream(sensor, (uint64_t(1) << 40) - 1); }

struct OutMessage {
  int64_t stamp = 0;
  int order = 0;  // among messages of one stamp: tf_static, odometry tick, sensors in rig order
  std::string topic;
  msg::Message message;
};

struct FrameJob {
  SimFrame frame;                       // sensor, index, stamp, t, poses in; ranges out
  const PeopleScene* people = nullptr;  // everyone present at the frame time
  std::vector<float> cos_incidence;     // ToF: |cos| of the angle between beam and surface
  std::vector<OutMessage> messages;
};

struct SensorSimOptions {
  bool noise_enabled = true;
  GlassMode glass = GlassMode::Transparent;  // the scenario's; SensorNoise::glass overrides
  int max_bounces = 8;
  uint64_t seed = 1;
};

class SensorSim {
 public:
  SensorSim(size_t index, const Sensor& sensor, const SensorNoise& noise, const SensorSimOptions& options,
            const Mesh& map, uint32_t person_label);

  const Sensor& sensor() const { return sensor_; }
  double rateHz() const { return sensor_.rateHz(); }
  // Fills frame.exact/measured/artefacts/label and the messages of every job.
  void simulate(const RayCaster& caster, std::vector<FrameJob>& jobs) const;
  // base -> sensor, and sensor -> optical for depth cameras.
  void staticTransforms(const std::string& base_frame, int64_t stamp,
                        std::vector<msg::TransformStamped>& out) const;

 private:
  void trace(const RayCaster& caster, std::vector<FrameJob>& jobs) const;
  void applyNoise(FrameJob& job) const;
  // Sensor-frame direction of beam b in frame `frame`, turned by the angle jitter.
  Eigen::Vector3f direction(size_t b, uint64_t frame) const;
  // Range of a neighbour of beam b across the largest step (flying or mixed pixel), or NaN.
  float edgeNeighbour(const SimFrame& f, size_t b, float* step) const;
  void buildMessages(FrameJob& job) const;

  size_t index_;
  Sensor sensor_;
  BeamSet beams_;
  SensorNoise noise_;
  SensorSimOptions opt_;
  GlassMode glass_;
  uint32_t glass_label_;  // kNoHit when the map has no glass
  uint32_t person_label_;
  std::vector<uint8_t> specular_;        // per label id
  std::vector<float> reflectivity_;      // per label id
  std::vector<float> depth_factor_;      // depth cameras: range -> depth
  int image_w_ = 0, image_h_ = 0;        // depth cameras: image size (0: a scanner)
  std::vector<float> beam_bias_;         // per beam, fixed over the run (empty: none)
  std::string optical_frame_;
};

}  // namespace polyloc::detail
