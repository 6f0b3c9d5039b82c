// Range sensor noise and artefacts. Defaults per sensor model come from data sheets
// (docs/simulation.md has the sources); every value can be overridden per scenario.
//
// What happens to one beam, in this order (each artefact is tagged, see ArtefactBits):
//   miss (nothing within range_max)                    -> +inf (REP-117 "no return")
//   dropout, probability `dropout` among returns        -> NaN  (REP-117 "erroneous")
//   max-range reading, `max_range` among the rest       -> range_max (no echo reported as max)
//   ToF: amplitude below `amplitude_min`                -> NaN
//   reflection outlier on a specular label (`reflection_outlier`): range * U(reflection_min, max)
//   flying (ToF) or mixed (laser) pixel at a depth discontinuity (`flying_pixel`): range mixed
//     between fore- and background (neighbours: the 4 pixels of a camera, beams b-1 and b+1 of
//     a scanner)
//   Gaussian noise: sigma(r) = max(sigma + sigma_slope * r, sigma_rel * r), plus `bias`, plus
//     the beam's own bias (`beam_bias`: drawn once per beam, the same in every frame)
// Before tracing, `angle_jitter` turns each beam of each frame about the sensor's z axis: the
// range is measured along another direction than the one the scan reports.
#pragma once

#include <polyloc/sensors/sensor.hpp>

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace polyloc {

enum class GlassMode { Transparent, Mirror, Opaque };
GlassMode parseGlassMode(const std::string& s);  // "transparent", "mirror", "opaque"
const char* glassModeName(GlassMode m);

// Per-beam tags, a bit mask: a beam may pass glass and then get noise, etc.
enum ArtefactBits : uint8_t {
  kArtefactNone = 0,
  kArtefactMiss = 1,           // nothing within range (not an artefact of the sensor)
  kArtefactDropout = 2,
  kArtefactMaxRange = 4,
  kArtefactGlassPassed = 8,    // went through glass (transparent)
  kArtefactGlassMirrored = 16, // reflected by glass (mirror)
  kArtefactFlyingPixel = 32,
  kArtefactReflection = 64,    // reflection outlier: implausibly short
  kArtefactDark = 128,         // ToF amplitude too low
};

struct SensorNoise {
  double sigma = 0.01;        // m, 1-sigma range noise
  double sigma_slope = 0.0;   // m per m of range, added to sigma
  double sigma_rel = 0.0;     // fraction of range, a floor: sigma(r) >= sigma_rel * r
  double bias = 0.0;          // m, added to every range
  double beam_bias = 0.0;     // m, 1-sigma of a per-beam range offset, fixed over frames
  double angle_jitter = 0.0;  // rad, 1-sigma azimuth error per beam and frame
  double dropout = 0.0;       // probability a return is lost
  double max_range = 0.0;     // probability of a spurious max-range reading
  std::optional<GlassMode> glass;  // overrides the scenario's glass mode for this sensor
  // Reflection outliers: on surfaces with a label in specular_labels.
  double reflection_outlier = 0.0;
  double reflection_min = 0.2, reflection_max = 0.8;  // fraction of the true range
  std::vector<std::string> specular_labels{"glass", "cabinet", "door"};
  double flying_pixel = 0.0;      // probability a discontinuity pixel/beam gets a mixed range
  double flying_threshold = 0.2;  // m, range (ToF: depth) step to a neighbour that makes a discontinuity
  // ToF only.
  double amplitude_scale = 1000;  // amplitude of a white surface (reflectivity 1) at 1 m, head on
  double amplitude_noise = 0.02;  // relative 1-sigma noise of the amplitude
  double amplitude_min = 0.0;     // pixels with a lower amplitude are invalid (NaN); 0 = off
  std::map<std::string, double> reflectivity;  // per label, overrides defaultReflectivity

  double sigmaAt(double range) const;
};

// Defaults by preset name (sensorPresetNames()); unknown presets get defaults by sensor kind.
SensorNoise defaultNoise(const std::string& preset, const SensorSpec& spec);
// Reflectivity (0..1) of a label for ToF amplitude: wall 0.8, floor 0.4, glass 0.1, ...
double defaultReflectivity(const std::string& label);

// Odometry drift: per step, with true translation dt (m) and rotation dr (rad, absolute),
//   rotation noise variance    = alpha1 dr + alpha2 dt   (rad^2)
//   translation noise variance = alpha3 dt + alpha4 dr   (m^2)
// Variances linear in the motion (not quadratic as in the textbook model), so the drift per
// metre and per radian does not depend on the odometry rate. On uneven floor the wheels measure
// the 3D distance (counted as planar), and each change of roll/pitch adds slip noise.
struct OdometryNoise {
  double alpha1 = 0.001;    // rad^2 per rad
  double alpha2 = 0.0005;   // rad^2 per m
  double alpha3 = 0.0004;   // m^2 per m
  double alpha4 = 0.0001;   // m^2 per rad
  double slip_translation = 0.001;  // m^2 per rad of roll/pitch change
  double slip_rotation = 0.002;     // rad^2 per rad of roll/pitch change
};

}  // namespace polyloc
