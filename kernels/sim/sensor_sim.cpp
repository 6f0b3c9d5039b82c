// Tracing and noise of one sensor's frames (see sensor_sim.hpp); messages are in
// sensor_messages.cpp.
#include "sensor_sim.hpp"

#include <polyloc/geometry/random.hpp>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace polyloc::detail {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kStep = 1e-4f;  // m past a glass surface before casting on

// Draw numbers k of one beam: normal() uses uniforms 2k and 2k+1, so uniforms start at 8.
enum Draw : uint64_t { kRangeNoise = 0, kAmplitudeNoise = 1, kBeamBias = 2, kJitter = 3, kDropout = 8, kMaxRange = 9,
                       kReflect = 10, kReflectFactor = 11, kFlying = 12, kFlyingMix = 13 };

// One beam still on its way after meeting glass.
struct Pending {
  size_t job, beam;
  Eigen::Vector3f o, d;  // origin and direction of the segment that met the glass
  float r;               // segment length to the glass
  Eigen::Vector3f n;     // glass normal
  float travelled;       // path length before the segment
  int bounces;
};

}  // namespace

SensorSim::SensorSim(size_t index, const Sensor& sensor, const SensorNoise& noise,
                     const SensorSimOptions& options, const Mesh& map, uint32_t person_label)
    : index_(index), sensor_(sensor), beams_(sensor.beams()), noise_(noise), opt_(options),
      glass_(noise.glass ? *noise.glass : options.glass), person_label_(person_label) {
  const int64_t g = map.findLabel("glass");
  glass_label_ = g < 0 ? kNoHit : static_cast<uint32_t>(g);
  specular_.assign(map.label_names.size(), 0);
  reflectivity_.assign(map.label_names.size(), 0.5f);
  for (size_t i = 0; i < map.label_names.size(); ++i) {
    const std::string& name = map.label_names[i];
    specular_[i] = std::find(noise.specular_labels.begin(), noise.specular_labels.end(), name) !=
                   noise.specular_labels.end();
    const auto it = noise.reflectivity.find(name);
    reflectivity_[i] = static_cast<float>(it != noise.reflectivity.end() ? it->second : defaultReflectivity(name));
  }
  if (const auto* cam = std::get_if<DepthCameraSpec>(&sensor.spec))
    depth_factor_ = cam->depthFactors(), image_w_ = cam->width, image_h_ = cam->height;
  optical_frame_ = sensor.name + "_optical";
  if (options.noise_enabled && noise.beam_bias > 0) {
    const CounterRng rng(options.seed);
    beam_bias_.resize(beams_.size());
    for (size_t b = 0; b < beams_.size(); ++b)
      beam_bias_[b] = static_cast<float>(noise.beam_bias * rng.normal(sensorStream(index), b, kBeamBias));
  }
}

Eigen::Vector3f SensorSim::direction(size_t b, uint64_t frame) const {
  const Eigen::Vector3f d(beams_.dx[b], beams_.dy[b], beams_.dz[b]);
  if (!opt_.noise_enabled || noise_.angle_jitter <= 0) return d;
  const double a = noise_.angle_jitter * CounterRng(opt_.seed).normal(frameStream(index_, frame), b, kJitter);
  const float c = static_cast<float>(std::cos(a)), s = static_cast<float>(std::sin(a));
  return {c * d.x() - s * d.y(), s * d.x() + c * d.y(), d.z()};
}

void SensorSim::simulate(const RayCaster& caster, std::vector<FrameJob>& jobs) const {
  if (jobs.empty()) return;
  trace(caster, jobs);
  tbb::parallel_for(size_t(0), jobs.size(), [&](size_t j) {
    applyNoise(jobs[j]);
    buildMessages(jobs[j]);
  });
}

void SensorSim::trace(const RayCaster& caster, std::vector<FrameJob>& jobs) const {
  const size_t nb = beams_.size(), nj = jobs.size(), n = nb * nj;
  std::vector<Pose> poses(nj);
  for (size_t j = 0; j < nj; ++j) poses[j] = jobs[j].frame.map_T_sensor;
  std::vector<float> range(n), nx(n), ny(n), nz(n);
  std::vector<uint32_t> label(n);
  const HitBuffers hits{range.data(), nullptr, label.data(), nx.data(), ny.data(), nz.data()};
  if (opt_.noise_enabled && noise_.angle_jitter > 0) {
    // Jittered beams are no longer one scan: explicit rays, each its own direction.
    std::vector<float> ox(n), oy(n), oz(n), dx(n), dy(n), dz(n), t0(n, beams_.range_min), t1(n, beams_.range_max);
    tbb::parallel_for(size_t(0), nj, [&](size_t j) {
      const Eigen::Matrix3f R = poses[j].rotation().toRotationMatrix().cast<float>();
      const Eigen::Vector3f o = poses[j].translation().cast<float>();
      for (size_t b = 0; b < nb; ++b) {
        const size_t i = j * nb + b;
        const Eigen::Vector3f d = R * direction(b, jobs[j].frame.index);
        ox[i] = o.x(), oy[i] = o.y(), oz[i] = o.z(), dx[i] = d.x(), dy[i] = d.y(), dz[i] = d.z();
      }
    });
    caster.castRays({ox.data(), oy.data(), oz.data(), dx.data(), dy.data(), dz.data(), t0.data(), t1.data(), n}, hits);
  } else {
    caster.castScans(poses, beams_, hits);
  }

  const bool tof = !depth_factor_.empty();
  const bool glass_on = glass_ != GlassMode::Opaque && glass_label_ != kNoHit && opt_.max_bounces > 0;
  const float rmin = beams_.range_min, rmax = beams_.range_max;
  std::vector<std::vector<Pending>> pending(nj);

  tbb::parallel_for(size_t(0), nj, [&](size_t j) {
    SimFrame& f = jobs[j].frame;
    f.exact.assign(nb, kInf);
    f.label.assign(nb, 0);
    f.artefacts.assign(nb, kArtefactNone);
    if (tof) jobs[j].cos_incidence.assign(nb, 0.f);
    const Eigen::Matrix3f R = poses[j].rotation().toRotationMatrix().cast<float>();
    const Eigen::Vector3f o = poses[j].translation().cast<float>();
    const PeopleScene* people = jobs[j].people && !jobs[j].people->empty() ? jobs[j].people : nullptr;
    for (size_t b = 0; b < nb; ++b) {
      const size_t i = j * nb + b;
      const Eigen::Vector3f d = R * direction(b, f.index);
      float r = range[i];
      Eigen::Vector3f normal(nx[i], ny[i], nz[i]);
      uint32_t lab = label[i];
      if (people) {
        Eigen::Vector3f pn;
        const float tp = people->intersect(o, d, rmin, std::min(r, rmax), &pn);
        if (tp < r) r = tp, lab = person_label_, normal = pn;
      }
      if (glass_on && std::isfinite(r) && lab == glass_label_) {
        pending[j].push_back({j, b, o, d, r, normal, 0.f, 0});
        continue;
      }
      if (std::isfinite(r)) {
        f.exact[b] = r;
        f.label[b] = lab;
        if (tof) jobs[j].cos_incidence[b] = std::abs(normal.dot(d));
      }
    }
  });

  // Glass: cast on from just past it (transparent) or reflected (mirror), all beams in one batch.
  std::vector<Pending> active;
  for (auto& p : pending) active.insert(active.end(), p.begin(), p.end());
  const bool mirror = glass_ == GlassMode::Mirror;
  std::vector<float> ox, oy, oz, dx, dy, dz, t0, t1, r2, nx2, ny2, nz2;
  std::vector<uint32_t> l2;
  while (!active.empty()) {
    const size_t m = active.size();
    for (auto* v : {&ox, &oy, &oz, &dx, &dy, &dz, &t0, &t1, &r2, &nx2, &ny2, &nz2}) v->resize(m);
    l2.resize(m);
    for (size_t k = 0; k < m; ++k) {
      Pending& p = active[k];
      const Eigen::Vector3f hit = p.o + p.d * p.r;
      jobs[p.job].frame.artefacts[p.beam] |= mirror ? kArtefactGlassMirrored : kArtefactGlassPassed;
      p.travelled += p.r;
      if (mirror) {
        Eigen::Vector3f nn = p.n.dot(p.d) > 0 ? Eigen::Vector3f(-p.n) : p.n;
        p.d = (p.d - 2.f * p.d.dot(nn) * nn).normalized();
        p.o = hit + nn * kStep;
      } else {
        p.o = hit + p.d * kStep;
        p.travelled += kStep;
      }
      ox[k] = p.o.x(), oy[k] = p.o.y(), oz[k] = p.o.z();
      dx[k] = p.d.x(), dy[k] = p.d.y(), dz[k] = p.d.z();
      t0[k] = 0.f, t1[k] = std::max(0.f, rmax - p.travelled);
    }
    caster.castRays({ox.data(), oy.data(), oz.data(), dx.data(), dy.data(), dz.data(), t0.data(), t1.data(), m},
                    {r2.data(), nullptr, l2.data(), nx2.data(), ny2.data(), nz2.data()});
    std::vector<Pending> next;
    for (size_t k = 0; k < m; ++k) {
      Pending& p = active[k];
      FrameJob& job = jobs[p.job];
      float r = t1[k] > 0.f ? r2[k] : kInf;
      Eigen::Vector3f normal(nx2[k], ny2[k], nz2[k]);
      uint32_t lab = l2[k];
      if (job.people && !job.people->empty() && t1[k] > 0.f) {
        Eigen::Vector3f pn;
        const float tp = job.people->intersect(p.o, p.d, 0.f, std::min(r, t1[k]), &pn);
        if (tp < r) r = tp, lab = person_label_, normal = pn;
      }
      if (!std::isfinite(r)) continue;  // a miss beyond the glass
      if (lab == glass_label_ && p.bounces + 1 < opt_.max_bounces) {
        next.push_back({p.job, p.beam, p.o, p.d, r, normal, p.travelled, p.bounces + 1});
        continue;
      }
      job.frame.exact[p.beam] = p.travelled + r;
      job.frame.label[p.beam] = lab;
      if (tof) job.cos_incidence[p.beam] = std::abs(normal.dot(p.d));
    }
    active.swap(next);
  }
}

void SensorSim::applyNoise(FrameJob& job) const {
  SimFrame& f = job.frame;
  const size_t nb = beams_.size();
  f.measured.assign(nb, kInf);
  const CounterRng rng(opt_.seed);
  const uint64_t stream = frameStream(index_, f.index);
  const bool tof = !depth_factor_.empty();
  const float rmax = beams_.range_max;
  for (size_t b = 0; b < nb; ++b) {
    float r = f.exact[b];
    if (!std::isfinite(r)) {
      f.artefacts[b] |= kArtefactMiss;
      continue;
    }
    if (!opt_.noise_enabled) {
      f.measured[b] = r;
      continue;
    }
    if (rng.uniform(stream, b, kDropout) < noise_.dropout) {
      f.measured[b] = kNaN, f.artefacts[b] |= kArtefactDropout;
      continue;
    }
    if (rng.uniform(stream, b, kMaxRange) < noise_.max_range) {
      f.measured[b] = rmax, f.artefacts[b] |= kArtefactMaxRange;
      continue;
    }
    const uint32_t lab = f.label[b];
    if (tof && noise_.amplitude_min > 0) {
      const float rr = std::max(r, 0.05f);
      const float a = static_cast<float>(noise_.amplitude_scale) * reflectivity_[std::min<size_t>(lab, reflectivity_.size() - 1)] *
                      job.cos_incidence[b] / (rr * rr);
      if (a < noise_.amplitude_min) {
        f.measured[b] = kNaN, f.artefacts[b] |= kArtefactDark;
        continue;
      }
    }
    if (lab < specular_.size() && specular_[lab] && rng.uniform(stream, b, kReflect) < noise_.reflection_outlier) {
      r *= static_cast<float>(rng.uniform(noise_.reflection_min, noise_.reflection_max, stream, b, kReflectFactor));
      f.artefacts[b] |= kArtefactReflection;
    } else if (noise_.flying_pixel > 0) {
      float step = 0.f;
      const float other = edgeNeighbour(f, b, &step);
      if (step > noise_.flying_threshold && rng.uniform(stream, b, kFlying) < noise_.flying_pixel) {
        const float k = tof ? depth_factor_[b] : 1.f;  // ToF pixels mix depths, lasers ranges
        const float d0 = r * k;
        const double mix = rng.uniform(0.1, 0.9, stream, b, kFlyingMix);
        r = static_cast<float>((std::min(d0, other) + mix * std::abs(other - d0)) / k);
        f.artefacts[b] |= kArtefactFlyingPixel;
      }
    }
    const float own_bias = beam_bias_.empty() ? 0.f : beam_bias_[b];
    f.measured[b] = static_cast<float>(r + noise_.bias + own_bias + noise_.sigmaAt(r) * rng.normal(stream, b, kRangeNoise));
  }
}

float SensorSim::edgeNeighbour(const SimFrame& f, size_t b, float* step) const {
  // Neighbours: the 4 pixels of a depth image (compared in depth), beams b-1 and b+1 of a scan.
  const int w = image_w_, h = image_h_;
  const auto value = [&](size_t i) { return w > 0 ? f.exact[i] * depth_factor_[i] : f.exact[i]; };
  const float v0 = value(b);
  float other = v0;
  *step = 0.f;
  const auto look = [&](size_t i) {
    const float vn = value(i);
    if (std::isfinite(vn) && std::abs(vn - v0) > *step) *step = std::abs(vn - v0), other = vn;
  };
  if (w > 0) {
    const int u = static_cast<int>(b % w), v = static_cast<int>(b / w);
    for (auto [du, dv] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
      const int uu = u + du, vv = v + dv;
      if (uu >= 0 && vv >= 0 && uu < w && vv < h) look(size_t(vv) * w + uu);
    }
  } else {
    if (b > 0) look(b - 1);
    if (b + 1 < f.exact.size()) look(b + 1);
  }
  return other;
}

}  // namespace polyloc::detail
