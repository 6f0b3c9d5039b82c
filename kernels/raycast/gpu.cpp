#include <polyloc/gpu/bvh.hpp>
#include <polyloc/raycast/gpu.hpp>
#include <polyloc/gpu/compute.hpp>
#include <polyloc/map/coincident_faces.hpp>
#include <polyloc/raycast/embree.hpp>

#include "../gpu/bindings.hpp"
#include "gpu_shaders.hpp"  // generated from gpu/shaders/*.glsl (kernels/CMakeLists.txt)

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <mutex>

namespace polyloc {
namespace {

using namespace gpu_bindings;
constexpr float kInf = std::numeric_limits<float>::infinity();
// Beyond this a float ray cannot be traced meaningfully (Embree's limit, raycast/embree.cpp).
constexpr float kRayLimit = 1e17f;

bool sane(float x) { return std::abs(x) <= kRayLimit; }  // false for NaN and inf
bool sane(const Eigen::Vector3f& v) { return sane(v.x()) && sane(v.y()) && sane(v.z()); }

std::string source(const char* defines, const char* body) {
  return std::string("#version 310 es\n") + glslDefines() + defines + shaders::kBvhTrace + body;
}

float asFloat(uint32_t bits) {
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

}  // namespace

struct GpuCaster::Impl {
  GpuCasterOptions opt;
  Mesh mesh;  // labels and normals of results; the fallback's map
  std::vector<float> nx, ny, nz;
  float tie_tol = 0;  // distances this close are one (ties decided as Embree decides them)
  GpuBvh bvh;
  std::unique_ptr<GpuContext> gpu;
  std::unique_ptr<ComputeProgram> scans, rays, free, score;
  // The map (uploaded once) and the batch buffers (grown to the largest batch seen).
  std::unique_ptr<StorageBuffer> nodes, verts, ids, in0, in1, hits, terms, tables, sums;
  int threads = 0;
  int batches = 0;
  std::unique_ptr<EmbreeCaster> fallback;
  std::mutex mu;
  // Host-side staging, reused between calls (calls are serialised by mu): no allocation per
  // batch once sizes settle, as the RayCaster contract asks.
  std::vector<float> stage0, stage1;
  std::vector<float> terms_host, tables_host, sums_host;  // scoreScans' staging
  std::vector<uint32_t> readback;
  std::vector<uint8_t> bad;
  std::vector<float> fallback_hits;  // scoreScans on Embree after a fallback

  void ensure(std::unique_ptr<StorageBuffer>& b, size_t bytes) {
    if (b && b->size() >= bytes) return;
    b.reset();
    b = std::make_unique<StorageBuffer>(*gpu, std::max<size_t>(bytes, 16));
  }

  // n invocations of the program in use: a second grid dimension past the x limit.
  void dispatch(const ComputeProgram& p, size_t n) const {
    const size_t groups = (n + kGroupSize - 1) / kGroupSize;
    const size_t gx = std::min(groups, size_t(gpu->info().max_work_group_count[0]));
    p.dispatch(uint32_t(gx), uint32_t((groups + gx - 1) / gx));
  }

  // The rays of one batch: count, windows of `beams` (scans) or per ray, and the options.
  void useCast(const ComputeProgram& p, size_t count, const CastOptions& o) const {
    p.use();
    p.set("count", uint32_t(count));
    p.set("backface_is_solid", uint32_t(o.backface_is_solid));
    p.set("miss_is_max_range", uint32_t(o.miss_is_max_range));
    p.set("tie_tol", tie_tol);
    nodes->bind(kNodes), verts->bind(kVerts), ids->bind(kTriIds), in0->bind(kIn0), in1->bind(kIn1), hits->bind(kHits);
  }

  // Beams as the scan program reads them: (d, t0), (t1, 0, 0, 0), windows merged with the limits.
  void uploadBeams(const BeamSet& beams, const ScanWindow& w) {
    std::vector<float>& b = stage1;
    b.assign(8 * beams.size(), 0.f);
    for (size_t i = 0; i < beams.size(); ++i) {
      const float t0 = w.tmin ? std::max(beams.range_min, w.tmin[i]) : beams.range_min;
      const float t1 = w.tmax ? std::min(beams.range_max, w.tmax[i]) : beams.range_max;
      const bool ok = sane(beams.dx[i]) && sane(beams.dy[i]) && sane(beams.dz[i]) && t0 <= t1;
      float* e = &b[8 * i];
      e[0] = beams.dx[i], e[1] = beams.dy[i], e[2] = beams.dz[i];
      e[3] = ok ? t0 : 1.f, e[4] = ok ? t1 : 0.f;  // an empty window misses
    }
    ensure(in1, b.size() * sizeof(float));
    in1->upload(b.data(), b.size() * sizeof(float));
  }

  // Poses [p0, p1) as three rows (R | t); a pose out of any sane domain is traced at the origin
  // and its rays are overwritten as misses afterwards (bad[]).
  void uploadPoses(std::span<const Pose> poses, size_t p0, size_t p1) {
    std::vector<float>& rows = stage0;
    rows.resize(12 * (p1 - p0));
    bad.assign(p1 - p0, 0);
    for (size_t p = p0; p < p1; ++p) {
      const Eigen::Matrix3f R = poses[p].rotation().toRotationMatrix().cast<float>();
      const Eigen::Vector3f t = poses[p].translation().cast<float>();
      const bool ok = sane(t) && R.allFinite();
      bad[p - p0] = !ok;
      float* r = &rows[12 * (p - p0)];
      for (int k = 0; k < 3; ++k) {
        r[4 * k] = ok ? R(k, 0) : float(k == 0), r[4 * k + 1] = ok ? R(k, 1) : float(k == 1);
        r[4 * k + 2] = ok ? R(k, 2) : float(k == 2), r[4 * k + 3] = ok ? t[k] : 0.f;
      }
    }
    ensure(in0, rows.size() * sizeof(float));
    in0->upload(rows.data(), rows.size() * sizeof(float));
  }

  // Casts poses [p0, p1) x the uploaded beams into `hits` (left on the GPU); returns the rays.
  size_t castChunk(std::span<const Pose> poses, size_t p0, size_t p1, size_t nb, const CastOptions& o) {
    const size_t n = (p1 - p0) * nb;
    uploadPoses(poses, p0, p1);
    ensure(hits, n * 8);
    useCast(*scans, n, o);
    scans->set("beams", uint32_t(nb));
    dispatch(*scans, n);
    return n;
  }

  // Writes results [i0, i0 + n) from the read-back (range bits, triangle) pairs.
  void finish(const HitBuffers& out, size_t i0, const std::vector<uint32_t>& h, size_t n) const {
    for (size_t k = 0; k < n; ++k) {
      const size_t i = i0 + k;
      const uint32_t t = h[2 * k + 1];
      out.range[i] = asFloat(h[2 * k]);
      if (out.triangle) out.triangle[i] = t;
      if (out.label) out.label[i] = t == kNoHit ? 0 : mesh.triangle_label[t];
      if (out.nx) {
        out.nx[i] = t == kNoHit ? 0.f : nx[t];
        out.ny[i] = t == kNoHit ? 0.f : ny[t];
        out.nz[i] = t == kNoHit ? 0.f : nz[t];
      }
    }
  }

  // Runs `gpu_work` with the context current; on a GpuError either rethrows or (fallback) warns
  // once and runs `cpu_work` on Embree, now and for every later call.
  template <class G, class C>
  void run(G&& gpu_work, C&& cpu_work) {
    std::lock_guard<std::mutex> lock(mu);
    if (!fallback) {
      try {
        gpu->makeCurrent();
        if (batches++ == opt.fail_batch)
          throw GpuError("gpu: the context was lost (EGL_CONTEXT_LOST; injected by fail_batch)");
        gpu_work();
        gpu->release();
        return;
      } catch (const GpuError& e) {
        try {
          gpu->release();
        } catch (const GpuError&) {
        }
        if (!opt.fallback) throw;
        const std::string msg = std::string(e.what()) + "; answering from Embree (CPU) from now on";
        opt.warn ? opt.warn(msg) : void(std::fprintf(stderr, "polyloc: warning: %s\n", msg.c_str()));
        EmbreeOptions eo;
        eo.threads = threads;
        fallback = std::make_unique<EmbreeCaster>(mesh, eo);
      }
    }
    cpu_work(*fallback);
  }
};

GpuCaster::GpuCaster(const Mesh& mesh, const GpuCasterOptions& options) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.opt = options;
  m.threads = options.threads;
  m.bvh = buildGpuBvh(mesh, options.max_leaf_size);
  m.tie_tol = coincidenceTolerance(mesh);
  m.mesh = mesh;
  const size_t nt = mesh.triangles.size();
  m.nx.resize(nt), m.ny.resize(nt), m.nz.resize(nt);
  for (size_t t = 0; t < nt; ++t) {
    const Eigen::Vector3f n = mesh.triangleNormal(t);
    m.nx[t] = n.x(), m.ny[t] = n.y(), m.nz[t] = n.z();
  }
  m.gpu = std::make_unique<GpuContext>(options.context);
  m.scans = std::make_unique<ComputeProgram>(*m.gpu, "raycast scans", source("#define SCANS 1\n", shaders::kRaycast));
  m.rays = std::make_unique<ComputeProgram>(*m.gpu, "raycast rays", source("#define SCANS 0\n", shaders::kRaycast));
  m.free = std::make_unique<ComputeProgram>(*m.gpu, "free space", source("", shaders::kFree));
  m.score = std::make_unique<ComputeProgram>(*m.gpu, "beam score", std::string("#version 310 es\nprecision highp float;\nprecision highp int;\n") + glslDefines() + shaders::kScore);
  m.ensure(m.nodes, m.bvh.nodes.size() * sizeof(GpuBvhNode));
  m.nodes->upload(m.bvh.nodes.data(), m.bvh.nodes.size() * sizeof(GpuBvhNode));
  m.ensure(m.verts, m.bvh.vertices.size() * sizeof(float));
  m.verts->upload(m.bvh.vertices.data(), m.bvh.vertices.size() * sizeof(float));
  m.ensure(m.ids, m.bvh.triangle.size() * sizeof(uint32_t));
  m.ids->upload(m.bvh.triangle.data(), m.bvh.triangle.size() * sizeof(uint32_t));
  m.gpu->release();
}

GpuCaster::~GpuCaster() {
  // GL objects go with the context: make it current on this thread to delete them.
  try {
    impl_->gpu->makeCurrent();
  } catch (const GpuError&) {
  }
  impl_->scans.reset(), impl_->rays.reset(), impl_->free.reset(), impl_->score.reset();
  for (auto* b : {&impl_->nodes, &impl_->verts, &impl_->ids, &impl_->in0, &impl_->in1, &impl_->hits, &impl_->terms,
                  &impl_->tables, &impl_->sums})
    b->reset();
}

// Under the batches' lock: a batch on another thread may be creating the fallback right now.
void GpuCaster::setThreads(int threads) {
  std::lock_guard<std::mutex> lock(impl_->mu);
  impl_->threads = threads;
  if (impl_->fallback) impl_->fallback->setThreads(threads);
}

int GpuCaster::threads() const {
  std::lock_guard<std::mutex> lock(impl_->mu);
  return impl_->threads;
}
const GpuInfo& GpuCaster::info() const { return impl_->gpu->info(); }
bool GpuCaster::fellBack() const {
  std::lock_guard<std::mutex> lock(impl_->mu);
  return impl_->fallback != nullptr;
}

size_t GpuCaster::memoryBytes() const {
  std::lock_guard<std::mutex> lock(impl_->mu);  // a call on another thread may be growing the buffers
  const Impl& m = *impl_;
  size_t gpu = 0;
  for (const auto* b : {&m.nodes, &m.verts, &m.ids, &m.in0, &m.in1, &m.hits, &m.terms, &m.tables, &m.sums})
    if (*b) gpu += (*b)->size();
  return gpu + m.nx.size() * 3 * sizeof(float) + m.mesh.triangle_label.size() * sizeof(uint32_t);
}

void GpuCaster::castScans(std::span<const Pose> poses, const BeamSet& beams, const HitBuffers& out,
                          const ScanWindow& window) const {
  Impl& m = *impl_;
  const size_t nb = beams.size();
  if (nb == 0 || poses.empty()) return;
  const CastOptions opt = options;
  m.run(
      [&] {
        m.uploadBeams(beams, window);
        const size_t chunk = std::max<size_t>(1, m.opt.batch_rays / nb);
        const std::vector<uint8_t>& bad = m.bad;
        std::vector<uint32_t>& h = m.readback;
        for (size_t p0 = 0; p0 < poses.size(); p0 += chunk) {
          const size_t p1 = std::min(poses.size(), p0 + chunk), n = m.castChunk(poses, p0, p1, nb, opt);
          h.resize(2 * n);
          m.hits->download(h.data(), n * 8);
          for (size_t p = p0; p < p1; ++p)
            if (bad[p - p0])
              for (size_t b = 0; b < nb; ++b) h[2 * ((p - p0) * nb + b)] = 0x7F800000u, h[2 * ((p - p0) * nb + b) + 1] = kNoHit;
          m.finish(out, p0 * nb, h, n);
        }
      },
      [&](EmbreeCaster& e) {
        e.options = opt;
        e.castScans(poses, beams, out, window);
      });
}

void GpuCaster::castRays(const RayBatch& r, const HitBuffers& out) const {
  Impl& m = *impl_;
  if (r.count == 0) return;
  const CastOptions opt = options;
  m.run(
      [&] {
        std::vector<float>&o = m.stage0, &d = m.stage1;
        std::vector<uint32_t>& h = m.readback;
        std::vector<uint8_t>& bad = m.bad;
        for (size_t i0 = 0; i0 < r.count; i0 += m.opt.batch_rays) {
          const size_t n = std::min(r.count - i0, m.opt.batch_rays);
          o.assign(4 * n, 0.f), d.assign(4 * n, 0.f), bad.assign(n, 0);
          for (size_t k = 0; k < n; ++k) {
            const size_t i = i0 + k;
            const float t0 = r.tmin ? r.tmin[i] : 0.f, t1 = r.tmax ? r.tmax[i] : kInf;
            const bool ok = sane(Eigen::Vector3f(r.ox[i], r.oy[i], r.oz[i])) &&
                            sane(Eigen::Vector3f(r.dx[i], r.dy[i], r.dz[i])) && t0 <= t1;
            bad[k] = !ok;
            o[4 * k] = ok ? r.ox[i] : 0.f, o[4 * k + 1] = ok ? r.oy[i] : 0.f, o[4 * k + 2] = ok ? r.oz[i] : 0.f;
            d[4 * k] = ok ? r.dx[i] : 1.f, d[4 * k + 1] = ok ? r.dy[i] : 0.f, d[4 * k + 2] = ok ? r.dz[i] : 0.f;
            o[4 * k + 3] = ok ? t0 : 1.f, d[4 * k + 3] = ok ? t1 : 0.f;  // an empty window misses
          }
          m.ensure(m.in0, o.size() * sizeof(float));
          m.ensure(m.in1, d.size() * sizeof(float));
          m.in0->upload(o.data(), o.size() * sizeof(float));
          m.in1->upload(d.data(), d.size() * sizeof(float));
          m.ensure(m.hits, n * 8);
          m.useCast(*m.rays, n, opt);
          m.dispatch(*m.rays, n);
          h.resize(2 * n);
          m.hits->download(h.data(), n * 8);
          m.finish(out, i0, h, n);
          // A ray out of any domain, or with a NaN window, is a miss (its own window end).
          for (size_t k = 0; k < n; ++k)
            if (bad[k]) {
              const float t1 = r.tmax ? r.tmax[i0 + k] : kInf;
              out.range[i0 + k] = opt.miss_is_max_range ? t1 : kInf;
            }
        }
      },
      [&](EmbreeCaster& e) {
        e.options = opt;
        e.castRays(r, out);
      });
}

void GpuCaster::queryFree(std::span<const Eigen::Vector3f> points, float clearance, uint8_t* free) const {
  Impl& m = *impl_;
  if (points.empty()) return;
  m.run(
      [&] {
        std::vector<float>& p = m.stage0;
        std::vector<uint32_t>& f = m.readback;
        for (size_t i0 = 0; i0 < points.size(); i0 += m.opt.batch_rays) {
          const size_t n = std::min(points.size() - i0, m.opt.batch_rays);
          p.assign(4 * n, 0.f);
          for (size_t k = 0; k < n; ++k)
            if (sane(points[i0 + k]))
              for (int c = 0; c < 3; ++c) p[4 * k + c] = points[i0 + k][c];
          m.ensure(m.in0, p.size() * sizeof(float));
          m.in0->upload(p.data(), p.size() * sizeof(float));
          m.ensure(m.hits, n * 4);
          m.free->use();
          m.free->set("count", uint32_t(n));
          m.free->set("clearance", std::max(0.f, clearance));
          m.nodes->bind(kNodes), m.verts->bind(kVerts), m.ids->bind(kTriIds), m.in0->bind(kIn0), m.hits->bind(kHits);
          m.dispatch(*m.free, n);
          f.resize(n);
          m.hits->download(f.data(), n * 4);
          for (size_t k = 0; k < n; ++k) free[i0 + k] = sane(points[i0 + k]) && f[k] == 1u ? 1 : 0;
        }
      },
      [&](EmbreeCaster& e) { e.queryFree(points, clearance, free); });
}

void GpuCaster::scoreScans(std::span<const Pose> poses, const BeamSet& beams, const ScanWindow& window,
                           const ScanScoring& s, double* sums) const {
  Impl& m = *impl_;
  const size_t nb = beams.size();
  if (nb == 0 || poses.empty()) return;
  const CastOptions opt = options;
  m.run(
      [&] {
        m.uploadBeams(beams, window);
        std::vector<float>& terms = m.terms_host;
        terms.assign(8 * nb, 0.f);
        for (size_t i = 0; i < nb; ++i) {
          float* t = &terms[8 * i];
          t[0] = s.measured[i], t[1] = s.miss[i], t[2] = s.short_dens[i], t[3] = s.hit_scale[i];
          t[4] = s.half_inv_var[i];
        }
        m.ensure(m.terms, terms.size() * sizeof(float));
        m.terms->upload(terms.data(), terms.size() * sizeof(float));
        std::vector<float>& tables = m.tables_host;
        tables.assign(2 * std::max<size_t>(s.table_size, 1), 0.f);
        if (s.table_size > 0) {
          std::copy(s.hit_table, s.hit_table + s.table_size, tables.begin());
          std::copy(s.log_table, s.log_table + s.table_size, tables.begin() + long(s.table_size));
        }
        m.ensure(m.tables, tables.size() * sizeof(float));
        m.tables->upload(tables.data(), tables.size() * sizeof(float));
        const size_t chunk = std::max<size_t>(1, m.opt.batch_rays / nb);
        const std::vector<uint8_t>& bad = m.bad;
        std::vector<float>& f = m.sums_host;
        for (size_t p0 = 0; p0 < poses.size(); p0 += chunk) {
          const size_t p1 = std::min(poses.size(), p0 + chunk), np = p1 - p0;
          m.castChunk(poses, p0, p1, nb, opt);
          m.ensure(m.sums, np * sizeof(float));
          m.score->use();
          m.score->set("poses", uint32_t(np));
          m.score->set("beams", uint32_t(nb));
          m.score->set("table_size", uint32_t(s.table_size));
          m.score->set("inv_step", s.inv_step);
          m.score->set("p_rand", s.p_rand);
          m.hits->bind(kHits), m.terms->bind(kTerms), m.tables->bind(kTables), m.sums->bind(kSums);
          m.dispatch(*m.score, np);
          f.resize(np);
          m.sums->download(f.data(), np * sizeof(float));
          for (size_t p = p0; p < p1; ++p) {
            double miss = 0;  // a pose out of any domain: every beam misses
            if (bad[p - p0])
              for (size_t i = 0; i < nb; ++i) miss += s.miss[i];
            sums[p] = bad[p - p0] ? miss : double(f[p - p0]);
          }
        }
      },
      [&](EmbreeCaster& e) {
        e.options = opt;
        std::vector<float>& h = impl_->fallback_hits;  // under run()'s lock
        h.resize(poses.size() * nb);
        e.castScans(poses, beams, {h.data()}, window);
        for (size_t p = 0; p < poses.size(); ++p) sums[p] = scoreHits(h.data() + p * nb, nb, s);
      });
}

}  // namespace polyloc
