// ToF/PMD depth filter settings, with defaults. The `depth_filter:` section of the polyloc config
// (maps/config/*.yaml) fills this struct; every field is a key there under the same name
// (docs/depth.md lists them with their defaults and the figures they give).
//
// The stages run in a fixed order, each one can be switched off:
//   validity -> jump_edge -> confidence -> smoothing -> points in the base frame
// Rejection comes before smoothing so that an outlier never bleeds into its neighbours' depth.
#pragma once

#include <optional>
#include <string>

namespace polyloc {

// Measurements that cannot be right on their own: outside the camera's range, too dark.
struct DepthValidity {
  std::optional<double> range_min;  // m along the pixel ray; absent: the camera's range_min
  std::optional<double> range_max;  // m; absent: the camera's range_max
  double amplitude_min = 0.0;       // darker pixels are rejected (0 = off); NaN amplitude always is
};

// Flying pixels (mixed fore-/background depth at a discontinuity) from the geometry of
// neighbouring points: where the 3D edge from a pixel to a neighbour runs within min_angle of
// the view ray, the two cannot both lie on one surface seen at a usable angle (Fuchs and May's
// jump-edge filter). `any` rejects both pixels of every such edge, the classic form; `between`
// only a pixel that, along one line (4 or 8 neighbours: 2 or 4 lines), has a jump to a nearer
// neighbour on one side and to a farther one on the other, as a depth mixed between a foreground
// and a background surface has: the rims of both surfaces and thin structures stay.
struct JumpEdgeFilter {
  bool enabled = true;
  double min_angle = 0.0872664625997165;  // rad (5 deg)
  std::string mode = "between";           // between | any
  int neighbours = 8;                     // 4 or 8
};

// The confidence filter of the thesis (eq. 6.4), iterated:
//   s_i <- sum_j s_j exp(-w_ij (d_i - d_j)^2 / sigma_d),  w_ij = exp(-|c_i - c_j|^2 / sigma_c)
// with three changes that make it work on real scenes (docs/depth.md has the figures):
//  - prediction `slope`: d_j is replaced by the depth that the neighbours in one direction
//    predict for pixel i along their surface (two-sided: interpolated between the nearest
//    confident pixels on either side; one-sided: extrapolated from the two nearest on one side;
//    in inverse depth, which is affine in the image for a plane). On a floor seen at a grazing
//    angle neighbouring depths differ by decimetres, which is no inconsistency. `neighbour`
//    keeps d_j itself, the formula as written.
//  - sigma_d is the squared expected error of that prediction: (sigma x noise(d_i) x gain)^2
//    with noise(d) = noise + noise_per_m d + noise_per_m2 d^2 (a ToF camera's error grows with d,
//    a structured-light camera's with d^2), so that the exponent is a squared z-score at any range.
//  - s is divided by max(predictions available, min_support), so it lies in [0, 1]: about 1 on
//    a smooth surface, near 0 for an isolated outlier, whatever holes or image borders are near.
// s_j is binary: a prediction uses the nearest pixels along a direction (up to `reach` away)
// that the previous iteration kept, so a good pixel among rejected ones is judged by good ones.
// Iteration t (1..iterations) keeps pixels with s >= threshold * t / iterations: early rounds
// drop only the clearly unsupported, later ones judge against a cleaner neighbourhood.
// c is the registered RGB (0..1 per channel) when given, else the logarithm of the amplitude
// (a ratio: the amplitude itself falls with 1/r^2); j is the nearest source pixel of the
// prediction. w_ij -> 0 across a colour edge, where a depth step is expected and not held
// against the pixel.
struct ConfidenceFilter {
  bool enabled = true;
  std::string prediction = "slope";  // slope | neighbour
  int iterations = 3;
  int reach = 4;                     // px along each of the 8 directions
  double sigma = 2.0;                // tolerance in multiples of the prediction's noise
  double noise = 0.002;              // m: depth noise (1 sigma) at 0 m ...
  double noise_per_m = 0.0008;       // ... plus this per metre (PMD O3D100: 2 mm + 0.8 mm/m) ...
  double noise_per_m2 = 0.0;         // ... plus this per square metre (structured light, Kinect: 1.6e-3)
  double sigma_c = 2.0;              // squared colour units (log-amplitude or RGB in 0..1)
  double threshold = 0.3;            // pixels whose confidence ends below this are rejected
  int min_support = 2;               // predictions counted at least, so one alone is not certainty
  std::string colour = "auto";       // auto (rgb, else amplitude) | rgb | amplitude | none
};

// Smoothing of the kept depth with OpenCV; rejected pixels are holes it does not fill.
struct DepthSmoothing {
  std::string method = "median";  // none | median (cv::medianBlur) | bilateral (cv::bilateralFilter)
  int size = 3;                   // median: 3 or 5; bilateral: diameter in pixels
  double sigma_depth = 0.03;      // m, bilateral range sigma
  double sigma_space = 1.5;       // px, bilateral spatial sigma
  double max_change = 0.05;       // m: a smoothed value further than this from the raw one is not taken
};

struct DepthFilterConfig {
  DepthValidity validity;
  JumpEdgeFilter jump_edge;
  ConfidenceFilter confidence;
  DepthSmoothing smoothing;
};

}  // namespace polyloc
