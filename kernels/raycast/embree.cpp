#include <polyloc/geometry/closest_point.hpp>
#include <polyloc/map/coincident_faces.hpp>
#include <polyloc/raycast/cast_arena.hpp>
#include <polyloc/raycast/embree.hpp>

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

namespace polyloc {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr int kPacket = 16;

// Directions for the inside-solid vote: irregular, so none runs along an axis-aligned wall.
const float kVoteDirs[3][3] = {{0.5377f, 0.8314f, 0.1397f},
                               {-0.7071f, 0.3162f, -0.6325f},
                               {0.1925f, -0.8660f, 0.4615f}};

struct ClearanceQuery {
  const Mesh* mesh;
  bool too_close = false;
};

bool clearanceCallback(RTCPointQueryFunctionArguments* args) {
  auto* q = static_cast<ClearanceQuery*>(args->userPtr);
  const Triangle& t = q->mesh->triangles[args->primID];
  const Eigen::Vector3f p(args->query->x, args->query->y, args->query->z);
  const Eigen::Vector3f c = closestPointOnTriangle(p, q->mesh->vertices[t[0]],
                                                   q->mesh->vertices[t[1]], q->mesh->vertices[t[2]]);
  if ((c - p).norm() < args->query->radius) {
    q->too_close = true;
    args->query->radius = 0.f;  // answer known: shrink the query so traversal ends
    return true;
  }
  return false;
}

// Embree asserts (aborting the process) on a ray whose origin or direction exceeds ~1.8e18 or
// whose window is NaN; such a ray reports a miss instead. Callers check their inputs
// (geometry/domain.hpp); this is the last defence.
constexpr float kRayLimit = 1e17f;
bool rayOk(float ox, float oy, float oz, float dx, float dy, float dz, float t0, float t1) {
  return std::abs(ox) <= kRayLimit && std::abs(oy) <= kRayLimit && std::abs(oz) <= kRayLimit &&
         std::abs(dx) <= kRayLimit && std::abs(dy) <= kRayLimit && std::abs(dz) <= kRayLimit && t0 <= t1 &&
         !std::isnan(t0) && !std::isnan(t1);
}

template <class Hit>
unsigned primOf(const Hit& hit, int k) {
  return hit.geomID[k] == RTC_INVALID_GEOMETRY_ID ? RTC_INVALID_GEOMETRY_ID : hit.primID[k];
}

// Ties. Touching closed solids (a cabinet against a wall, furniture on the floor slab) share
// faces. A ray from inside one (a particle inside furniture, a random pose in a wall) meets its
// exit face and the neighbour's entry face at the same distance, and Embree keeps whichever its
// traversal met last: packets and single rays then disagree (0 m or the neighbour's face). The
// tie filter makes the answer independent of the order: at one distance a back face wins (the
// origin is inside a solid: backface_is_solid gives the window start, as for any ray from
// inside), then the lower triangle index. Only rays whose hit lies where such faces overlap
// (map/coincident_faces.hpp: a floor under the furniture, not the whole floor) are cast again
// with it: a filter on every ray cost 13-20% of the packets' and the localiser's speed, and
// casting again every hit on a partly covered triangle cost the localiser a third (tilted
// scanners see the floor all the time). The filter runs on single rays only (recast). Distances
// within `tol` are one distance (CoincidentFaces::tolerance(): far from the origin the two
// faces' distances differ by float steps); the filter refuses every candidate and keeps the
// best itself, so that a preferred face a step farther than the first one met still wins.
struct TieContext {
  RTCIntersectContext ctx;  // first member: Embree passes &ctx to the filter
  const float *nx, *ny, *nz;
  float tol = 0;
  float t = kInf;  // the kept hit
  unsigned prim = RTC_INVALID_GEOMETRY_ID;

  TieContext(const float* x, const float* y, const float* z, float tolerance) : nx(x), ny(y), nz(z), tol(tolerance) {
    rtcInitIntersectContext(&ctx);
    ctx.filter = tieFilter;
  }
  bool back(unsigned p, RTCRayN* ray) const {
    return nx[p] * RTCRayN_dir_x(ray, 1, 0) + ny[p] * RTCRayN_dir_y(ray, 1, 0) + nz[p] * RTCRayN_dir_z(ray, 1, 0) > 0.f;
  }

  // Called for every candidate hit: a nearer one (beyond the tolerance) replaces the kept one;
  // facing is looked at on ties alone. Every candidate is refused, so Embree offers them all.
  static void tieFilter(const RTCFilterFunctionNArguments* args) {
    auto* c = reinterpret_cast<TieContext*>(args->context);
    if (args->valid[0] != -1) return;
    const float t = RTCRayN_tfar(args->ray, 1, 0);  // the candidate's distance
    const unsigned prim = RTCHitN_primID(args->hit, 1, 0);
    args->valid[0] = 0;
    if (c->prim != RTC_INVALID_GEOMETRY_ID && std::abs(t - c->t) <= c->tol) {
      const bool back = c->back(prim, args->ray), kept_back = c->back(c->prim, args->ray);
      if (back != kept_back ? !back : prim > c->prim) return;
    } else if (t > c->t) {
      return;
    }
    c->t = t, c->prim = prim;
  }
};

}  // namespace

// Owns the device and scene: released here, so also when the constructor throws half-way.
struct EmbreeCaster::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
  Mesh mesh;  // copy: labels, normals and vertices for results and clearance queries
  std::vector<float> nx, ny, nz;
  CastArena pool;
  std::atomic<int64_t> device_bytes{0};  // Embree's memory monitor: allocated minus freed
  CoincidentFaces coincident;            // where faces lie on faces facing the other way

  // Whether the hit at `t` on `prim` lies where another face covers it: a tie is possible there.
  bool tied(unsigned prim, float ox, float oy, float oz, float dx, float dy, float dz, float t) const {
    return coincident.any() && prim != RTC_INVALID_GEOMETRY_ID && coincident.has(prim) &&
           coincident.covers(prim, Eigen::Vector3f(ox + t * dx, oy + t * dy, oz + t * dz));
  }

  // One ray again with the tie rule, when its hit lies on a coincident face: its distance and
  // triangle replace `tfar` and `prim`.
  void recast(float ox, float oy, float oz, float dx, float dy, float dz, float t0, float t1, float& tfar,
              unsigned& prim) const {
    TieContext tie(nx.data(), ny.data(), nz.data(), coincident.tolerance());
    RTCRayHit rh;
    // Up to just beyond the first pass's hit: the faces tied with it, nothing farther.
    rh.ray = {ox, oy, oz, t0, dx, dy, dz, 0.f, std::min(t1, tfar + 2 * tie.tol), 0xFFFFFFFFu, 0, 0};
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &tie.ctx, &rh);
    if (tie.prim == RTC_INVALID_GEOMETRY_ID) return;  // cannot be (the first pass hit): keep its answer
    tfar = tie.t, prim = tie.prim;
  }

  // Writes one ray's result; `dir` is the unit direction, `t0`/`t1` the window.
  void finish(const HitBuffers& out, size_t i, float tfar, unsigned prim, float dx, float dy,
              float dz, float t0, float t1, const CastOptions& opt) const {
    if (prim == RTC_INVALID_GEOMETRY_ID) {
      out.range[i] = opt.miss_is_max_range ? t1 : kInf;
      if (out.triangle) out.triangle[i] = kNoHit;
      if (out.label) out.label[i] = 0;
      if (out.nx) out.nx[i] = out.ny[i] = out.nz[i] = 0.f;
      return;
    }
    const bool back = nx[prim] * dx + ny[prim] * dy + nz[prim] * dz > 0.f;
    out.range[i] = back && opt.backface_is_solid ? t0 : tfar;
    if (out.triangle) out.triangle[i] = prim;
    if (out.label) out.label[i] = mesh.triangle_label[prim];
    if (out.nx) {
      out.nx[i] = nx[prim];
      out.ny[i] = ny[prim];
      out.nz[i] = nz[prim];
    }
  }
};

EmbreeCaster::EmbreeCaster(const Mesh& mesh, const EmbreeOptions& options) : impl_(new Impl) {
  Impl& m = *impl_;
  if (mesh.triangles.empty()) throw std::invalid_argument("EmbreeCaster: the map has no triangles");
  m.mesh = mesh;
  m.device = rtcNewDevice(options.device_config.empty() ? nullptr : options.device_config.c_str());
  if (!m.device) throw std::runtime_error("Embree: cannot create device (error " +
                                          std::to_string(rtcGetDeviceError(nullptr)) + ")");
  rtcSetDeviceMemoryMonitorFunction(
      m.device,
      [](void* user, ssize_t bytes, bool) {
        static_cast<std::atomic<int64_t>*>(user)->fetch_add(bytes, std::memory_order_relaxed);
        return true;
      },
      &m.device_bytes);
  m.scene = rtcNewScene(m.device);
  rtcSetSceneFlags(m.scene, RTCSceneFlags((options.robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE) |
                                          RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION));  // tieFilter
  rtcSetSceneBuildQuality(m.scene, options.high_quality_bvh ? RTC_BUILD_QUALITY_HIGH
                                                            : RTC_BUILD_QUALITY_MEDIUM);
  const std::unique_ptr<RTCGeometryTy, decltype(&rtcReleaseGeometry)> owned(rtcNewGeometry(m.device, RTC_GEOMETRY_TYPE_TRIANGLE),
                                                                           &rtcReleaseGeometry);
  RTCGeometry geom = owned.get();
  // Embree-owned buffers are padded as its SIMD loads require.
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0,
                                                        RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                        mesh.vertices.size()));
  for (size_t i = 0; i < mesh.vertices.size(); ++i)
    for (int k = 0; k < 3; ++k) v[3 * i + k] = mesh.vertices[i][k];
  auto* idx = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0,
                                                             RTC_FORMAT_UINT3, 3 * sizeof(uint32_t),
                                                             mesh.triangles.size()));
  const size_t nt = mesh.triangles.size();
  m.nx.resize(nt);
  m.ny.resize(nt);
  m.nz.resize(nt);
  for (size_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) {
      if (mesh.triangles[t][k] >= mesh.vertices.size())
        throw std::invalid_argument("EmbreeCaster: triangle " + std::to_string(t) +
                                    " references a missing vertex");
      idx[3 * t + k] = mesh.triangles[t][k];
    }
    const Eigen::Vector3f n = mesh.triangleNormal(t);
    m.nx[t] = n.x();
    m.ny[t] = n.y();
    m.nz[t] = n.z();
  }
  m.coincident = CoincidentFaces(mesh);
  rtcSetGeometryPointQueryFunction(geom, clearanceCallback);
  rtcCommitGeometry(geom);
  rtcAttachGeometry(m.scene, geom);
  rtcCommitScene(m.scene);
  if (rtcGetDeviceError(m.device) != RTC_ERROR_NONE)
    throw std::runtime_error("Embree: scene build failed for " + mesh.source);
  setThreads(options.threads);
}

size_t EmbreeCaster::memoryBytes() const {
  const Mesh& s = impl_->mesh;
  const size_t kept = s.vertices.size() * sizeof(Eigen::Vector3f) + s.triangles.size() * (sizeof(Triangle) + sizeof(uint32_t)) +
                      impl_->nx.size() * 3 * sizeof(float);
  return size_t(std::max<int64_t>(0, impl_->device_bytes.load(std::memory_order_relaxed))) + kept;
}

EmbreeCaster::~EmbreeCaster() = default;

void EmbreeCaster::setThreads(int threads) { impl_->pool.resize(threads); }

int EmbreeCaster::threads() const { return impl_->pool.threads(); }

void EmbreeCaster::castScans(std::span<const Pose> poses, const BeamSet& beams,
                             const HitBuffers& out, const ScanWindow& window) const {
  const Impl& m = *impl_;
  const size_t nb = beams.size();
  if (nb == 0 || poses.empty()) return;
  const CastOptions opt = options;
  m.pool.parallel(poses.size(), 4, [&](size_t p0, size_t p1) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;  // the beams of one pose share an origin
    alignas(64) RTCRayHit16 rh;
    alignas(64) int valid[kPacket];
    float t0[kPacket], t1[kPacket];  // windows, kept because Embree overwrites tfar
    for (size_t p = p0; p < p1; ++p) {
      const Eigen::Matrix3f R = poses[p].rotation().toRotationMatrix().cast<float>();
      const Eigen::Vector3f o = poses[p].translation().cast<float>();
      for (size_t b0 = 0; b0 < nb; b0 += kPacket) {
        const int n = static_cast<int>(std::min<size_t>(kPacket, nb - b0));
        for (int k = 0; k < kPacket; ++k) {
          const size_t b = b0 + std::min(k, n - 1);  // pad lanes with a real ray, masked off
          const Eigen::Vector3f d = R * Eigen::Vector3f(beams.dx[b], beams.dy[b], beams.dz[b]);
          rh.ray.org_x[k] = o.x();
          rh.ray.org_y[k] = o.y();
          rh.ray.org_z[k] = o.z();
          rh.ray.dir_x[k] = d.x();
          rh.ray.dir_y[k] = d.y();
          rh.ray.dir_z[k] = d.z();
          rh.ray.tnear[k] = window.tmin ? std::max(beams.range_min, window.tmin[b]) : beams.range_min;
          rh.ray.tfar[k] = window.tmax ? std::min(beams.range_max, window.tmax[b]) : beams.range_max;
          rh.ray.time[k] = 0.f;
          rh.ray.mask[k] = 0xFFFFFFFFu;
          rh.ray.id[k] = 0;
          rh.ray.flags[k] = 0;
          rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
          // An empty window sees nothing: its lane stays off and reports a miss.
          valid[k] = k < n && rayOk(o.x(), o.y(), o.z(), d.x(), d.y(), d.z(), rh.ray.tnear[k], rh.ray.tfar[k])
                         ? -1 : 0;
          t0[k] = rh.ray.tnear[k];
          t1[k] = rh.ray.tfar[k];
        }
        rtcIntersect16(valid, m.scene, &ctx, &rh);
        for (int k = 0; k < n; ++k) {
          float tfar = rh.ray.tfar[k];
          unsigned prim = primOf(rh.hit, k);
          if (m.tied(prim, o.x(), o.y(), o.z(), rh.ray.dir_x[k], rh.ray.dir_y[k], rh.ray.dir_z[k], tfar))
            m.recast(o.x(), o.y(), o.z(), rh.ray.dir_x[k], rh.ray.dir_y[k], rh.ray.dir_z[k], t0[k], t1[k], tfar, prim);
          m.finish(out, p * nb + b0 + k, tfar, prim, rh.ray.dir_x[k], rh.ray.dir_y[k], rh.ray.dir_z[k], t0[k], t1[k], opt);
        }
      }
    }
  });
}

void EmbreeCaster::castScansSingle(std::span<const Pose> poses, const BeamSet& beams,
                                   float* range) const {
  const Impl& m = *impl_;
  const size_t nb = beams.size();
  const CastOptions opt = options;
  const HitBuffers out{range};
  m.pool.parallel(poses.size(), 4, [&](size_t p0, size_t p1) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    for (size_t p = p0; p < p1; ++p) {
      const Eigen::Matrix3f R = poses[p].rotation().toRotationMatrix().cast<float>();
      const Eigen::Vector3f o = poses[p].translation().cast<float>();
      for (size_t b = 0; b < nb; ++b) {
        const Eigen::Vector3f d = R * Eigen::Vector3f(beams.dx[b], beams.dy[b], beams.dz[b]);
        rh.ray = {o.x(), o.y(), o.z(), beams.range_min, d.x(), d.y(), d.z(), 0.f,
                  beams.range_max, 0xFFFFFFFFu, 0, 0};
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        if (rayOk(o.x(), o.y(), o.z(), d.x(), d.y(), d.z(), beams.range_min, beams.range_max))
          rtcIntersect1(m.scene, &ctx, &rh);
        float tfar = rh.ray.tfar;
        unsigned prim = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? RTC_INVALID_GEOMETRY_ID : rh.hit.primID;
        if (m.tied(prim, o.x(), o.y(), o.z(), d.x(), d.y(), d.z(), tfar))
          m.recast(o.x(), o.y(), o.z(), d.x(), d.y(), d.z(), beams.range_min, beams.range_max, tfar, prim);
        m.finish(out, p * nb + b, tfar, prim, d.x(), d.y(), d.z(), beams.range_min, beams.range_max, opt);
      }
    }
  });
}

void EmbreeCaster::castRays(const RayBatch& rays, const HitBuffers& out) const {
  const Impl& m = *impl_;
  const CastOptions opt = options;
  const size_t npk = (rays.count + kPacket - 1) / kPacket;
  m.pool.parallel(npk, 64, [&](size_t q0, size_t q1) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    alignas(64) RTCRayHit16 rh;
    alignas(64) int valid[kPacket];
    float t0[kPacket], t1[kPacket];
    for (size_t q = q0; q < q1; ++q) {
      const size_t i0 = q * kPacket;
      const int n = static_cast<int>(std::min<size_t>(kPacket, rays.count - i0));
      for (int k = 0; k < kPacket; ++k) {
        const size_t i = i0 + std::min(k, n - 1);
        rh.ray.org_x[k] = rays.ox[i];
        rh.ray.org_y[k] = rays.oy[i];
        rh.ray.org_z[k] = rays.oz[i];
        rh.ray.dir_x[k] = rays.dx[i];
        rh.ray.dir_y[k] = rays.dy[i];
        rh.ray.dir_z[k] = rays.dz[i];
        rh.ray.tnear[k] = t0[k] = rays.tmin ? rays.tmin[i] : 0.f;
        rh.ray.tfar[k] = t1[k] = rays.tmax ? rays.tmax[i] : kInf;
        rh.ray.time[k] = 0.f;
        rh.ray.mask[k] = 0xFFFFFFFFu;
        rh.ray.id[k] = 0;
        rh.ray.flags[k] = 0;
        rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
        valid[k] = k < n && rayOk(rays.ox[i], rays.oy[i], rays.oz[i], rays.dx[i], rays.dy[i], rays.dz[i],
                                  t0[k], t1[k])
                       ? -1 : 0;
      }
      rtcIntersect16(valid, m.scene, &ctx, &rh);
      for (int k = 0; k < n; ++k) {
        float tfar = rh.ray.tfar[k];
        unsigned prim = primOf(rh.hit, k);
        if (m.tied(prim, rh.ray.org_x[k], rh.ray.org_y[k], rh.ray.org_z[k], rh.ray.dir_x[k], rh.ray.dir_y[k],
                   rh.ray.dir_z[k], tfar))
          m.recast(rh.ray.org_x[k], rh.ray.org_y[k], rh.ray.org_z[k], rh.ray.dir_x[k], rh.ray.dir_y[k], rh.ray.dir_z[k],
                   t0[k], t1[k], tfar, prim);
        m.finish(out, i0 + k, tfar, prim, rh.ray.dir_x[k], rh.ray.dir_y[k], rh.ray.dir_z[k], t0[k], t1[k], opt);
      }
    }
  });
}

// Inside: the first surface met is a back face for most of three irregular directions (a point
// inside a closed solid sees only back faces). Clearance: an Embree point query of radius r.
void EmbreeCaster::queryFree(std::span<const Eigen::Vector3f> points, float clearance,
                             uint8_t* free) const {
  const Impl& m = *impl_;
  m.pool.parallel(points.size(), 64, [&](size_t i0, size_t i1) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCPointQueryContext pctx;
    for (size_t i = i0; i < i1; ++i) {
      const Eigen::Vector3f& p = points[i];
      if (!rayOk(p.x(), p.y(), p.z(), 0.f, 0.f, 0.f, 0.f, 0.f)) {
        free[i] = 0;  // nowhere a robot can stand
        continue;
      }
      int back = 0;
      for (const auto& d : kVoteDirs) {
        RTCRayHit rh;
        rh.ray = {p.x(), p.y(), p.z(), 0.f, d[0], d[1], d[2], 0.f, kInf, 0xFFFFFFFFu, 0, 0};
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(m.scene, &ctx, &rh);
        float tfar = rh.ray.tfar;
        unsigned t = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? RTC_INVALID_GEOMETRY_ID : rh.hit.primID;
        if (m.tied(t, p.x(), p.y(), p.z(), d[0], d[1], d[2], tfar)) m.recast(p.x(), p.y(), p.z(), d[0], d[1], d[2], 0.f, kInf, tfar, t);
        if (t != RTC_INVALID_GEOMETRY_ID) back += m.nx[t] * d[0] + m.ny[t] * d[1] + m.nz[t] * d[2] > 0.f;
      }
      bool ok = back < 2;
      if (ok && clearance > 0.f) {
        RTCPointQuery q{p.x(), p.y(), p.z(), 0.f, clearance};
        ClearanceQuery cq{&m.mesh};
        rtcInitPointQueryContext(&pctx);
        rtcPointQuery(m.scene, &q, &pctx, nullptr, &cq);
        ok = !cq.too_close;
      }
      free[i] = ok ? 1 : 0;
    }
  });
}

}  // namespace polyloc
