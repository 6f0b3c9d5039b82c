#include <polyloc/depth/filter.hpp>
#include <polyloc/eval/rgbd_eval.hpp>
#include <polyloc/map/load.hpp>
#include <polyloc/mcl/refine.hpp>
#include <polyloc/raycast/factory.hpp>

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <optional>
#include <cmath>
#include <stdexcept>

namespace polyloc {
namespace {

// Stages in the order the filter runs them; the first that rejects a pixel owns it.
constexpr std::pair<DepthReject, const char*> kStages[] = {
    {DepthReject::kRange, "range"}, {DepthReject::kJumpEdge, "jump_edge"}, {DepthReject::kConfidence, "confidence"}};

// The camera's pixels at the truth, against the mesh: depth along the optical axis, NaN where no
// surface is within the camera's range.
void renderDepth(const RayCaster& caster, const DepthCameraSpec& cam, const BeamSet& beams, const std::vector<float>& factor,
                 const Pose& pose, std::vector<float>& range, std::vector<float>& depth) {
  range.resize(beams.size());
  depth.resize(beams.size());
  caster.castScans(std::span<const Pose>(&pose, 1), beams, {range.data()});
  for (size_t b = 0; b < beams.size(); ++b)
    depth[b] = std::isfinite(range[b]) && range[b] <= cam.range_max ? range[b] * factor[b] : NAN;
}

}  // namespace

RefineConfig RgbdEvalOptions::floorRefineDefaults() {
  RefineConfig r;
  r.iterations = 30;
  r.beams_per_scan = 2000;
  r.search_xy = 0, r.search_yaw = 0;  // ICP from the truth, no search
  r.max_correspondence = 0.1;
  r.huber = 0.02;
  r.min_inlier_ratio = 0.3;
  r.max_correction = 0.3;
  r.max_correction_yaw = 0.2;
  return r;
}

RgbdEvalResult evaluateRgbd(const std::string& input, const RgbdEvalOptions& o) {
  using Clock = std::chrono::steady_clock;
  RgbdEvalResult res;
  res.input = input;
  auto progress = [&](const std::string& stage, double f) { if (o.progress) o.progress(stage, f); };
  Mesh mesh;
  if (!o.map.empty()) {
    mesh = loadMesh(o.map);
    res.map = o.map;
  } else {
    auto reader = openRecording(input);
    mesh = fuseRecording(*reader, input, o.fusion, FrameSelection::parse("even"), res.fusion,
                         [&](double f) { progress("fusing the even frames", f); });
    if (mesh.triangles.empty())
      throw std::runtime_error(fmt::format("{}: no even frame with a pose to fuse a map from", input));
    res.fused = true;
    res.map = "(fused from the even frames)";
  }
  res.map_triangles = mesh.numTriangles();
  const auto caster = makeCaster("embree", mesh);
  const FrameSelection selection = FrameSelection::parse(!o.frames.empty() ? o.frames : res.fused ? "odd" : "all");

  // Depth ranges: the fusion's, so that labels cover what the map was made of.
  std::optional<DepthFilter> filter;
  Rig rig;
  BeamSet beams;
  std::vector<float> factor, range, rendered, ranges;
  res.filter.resize(std::size(kStages) + 1);
  for (size_t s = 0; s < std::size(kStages); ++s) res.filter[s].name = kStages[s].second;
  res.filter.back().name = "filter";
  DepthFilterResult filtered;
  double sum_t2 = 0, sum_r2 = 0;
  size_t evaluated = 0;
  auto reader = openRecording(input);
  int64_t sample = o.sample_frame;
  if (sample < 0) {  // past the middle of the images
    for (const TopicInfo& t : reader->topics())
      if (t.type == "sensor_msgs/msg/Image") sample = std::max<int64_t>(sample, int64_t(t.count / 2));
  }
  PosedFrameStats st;
  forEachPosedFrame(
      *reader, input, selection, o.fusion.min_depth, o.fusion.max_depth, st,
      [&](const PosedFrame& f) {
        if (!filter) {
          res.camera = st.camera;
          filter.emplace(st.camera, Pose(), o.filter);
          rig.add({"camera", st.camera, Pose()}, "recorded");
          beams = st.camera.beams();
          factor = st.camera.depthFactors();
        }
        RgbdFrameResult fr;
        fr.index = f.index, fr.stamp_ns = f.stamp_ns, fr.truth = f.world_T_body;
        renderDepth(*caster, st.camera, beams, factor, f.world_T_body, range, rendered);

        // Labels, then what each stage removed of them.
        const auto t0 = Clock::now();
        filter->apply({st.camera.width, st.camera.height, f.depth.data()}, filtered);
        res.filter_seconds += std::chrono::duration<double>(Clock::now() - t0).count();
        const int w = st.camera.width, h = st.camera.height, k = std::max(o.tolerance.align_px, 0);
        const bool keep = res.sample.index < 0 && f.index >= sample;
        if (keep) {
          res.sample.index = f.index;
          res.sample.measured = f.depth, res.sample.rendered = rendered, res.sample.kept = filtered.valid;
          res.sample.label.assign(f.depth.size(), uint8_t(RgbdLabel::kNone));
        }
        auto mark = [&](size_t b, RgbdLabel l) { if (keep) res.sample.label[b] = uint8_t(l); };
        for (size_t b = 0; b < f.depth.size(); ++b) {
          const float z = f.depth[b];
          if (!(z > 0)) continue;  // no measurement: nothing to judge
          const float tol = float(o.tolerance.at(z));
          const bool outlier = !(std::abs(z - rendered[b]) <= tol);  // NaN rendered: not good
          if (!outlier) {
            ++fr.good;
            mark(b, RgbdLabel::kGood);
          } else {
            // Does a rendered pixel within k agree? Then the edge may just lie a pixel or two off.
            const int u = int(b % size_t(w)), v = int(b / size_t(w));
            bool near = false;
            for (int dv = -k; dv <= k && !near; ++dv)
              for (int du = -k; du <= k && !near; ++du) {
                const int uu = u + du, vv = v + dv;
                if (uu >= 0 && vv >= 0 && uu < w && vv < h) near = std::abs(z - rendered[size_t(vv) * w + uu]) <= tol;
              }
            if (near) {
              ++fr.ambiguous, mark(b, RgbdLabel::kAmbiguous);
              continue;
            }
            if (!std::isfinite(rendered[b])) {
              ++fr.unlabelled, mark(b, RgbdLabel::kUnlabelled);
              continue;
            }
            ++fr.outliers, mark(b, RgbdLabel::kOutlier);
          }
          const DepthReject why = filtered.reason[b];
          for (size_t s = 0; s < std::size(kStages); ++s) {
            RgbdFilterStage& stage = res.filter[s];
            stage.outliers += outlier;
            if (why == kStages[s].first) ++stage.removed, ++(outlier ? stage.removed_outliers : stage.removed_good);
          }
          RgbdFilterStage& all = res.filter.back();
          all.outliers += outlier;
          if (why != DepthReject::kKept && why != DepthReject::kNoMeasurement)
            ++all.removed, ++(outlier ? all.removed_outliers : all.removed_good);
        }
        res.outliers += fr.outliers, res.good += fr.good, res.ambiguous += fr.ambiguous, res.unlabelled += fr.unlabelled;

        // The floor: ICP from the truth against the mesh.
        if (evaluated++ % std::max<size_t>(o.floor_every, 1) == 0) {
          ranges.resize(f.depth.size());
          for (size_t b = 0; b < f.depth.size(); ++b) ranges[b] = f.depth[b] > 0 ? f.depth[b] / factor[b] : NAN;
          const RefineScan scan{0, ranges, Pose()};
          const RefineResult r = refinePose(*caster, rig, std::span<const RefineScan>(&scan, 1), f.world_T_body, 6, o.floor_refine);
          fr.floor_ok = r.accepted;
          if (r.accepted) {
            const Pose d = f.world_T_body.inverse() * r.pose;
            fr.floor_translation = d.translation().norm();
            fr.floor_rotation = Eigen::AngleAxisd(d.rotation()).angle();
            fr.floor_rms = r.rms;
            sum_t2 += fr.floor_translation * fr.floor_translation, sum_r2 += fr.floor_rotation * fr.floor_rotation;
            ++res.floor_frames;
          } else {
            ++res.floor_failed;
          }
        }
        res.frames.push_back(fr);
      },
      [&](double f) { progress("evaluating frames", f); });
  if (res.frames.empty())
    throw std::runtime_error(fmt::format("{}: no frame to evaluate ({} depth frames, {} selected, {} without a pose)",
                                         input, st.images, st.selected, st.without_pose));
  if (res.floor_frames) {
    res.floor_rmse_translation = std::sqrt(sum_t2 / double(res.floor_frames));
    res.floor_rmse_rotation = std::sqrt(sum_r2 / double(res.floor_frames));
  }
  return res;
}

}  // namespace polyloc
