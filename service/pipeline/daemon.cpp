#include "pipeline/daemon.hpp"

#include "pipeline/pipeline.hpp"
#include "pipeline/shm_payloads.hpp"
#include "pipeline/input_gate.hpp"
#include "shm/channel.hpp"

#include <polyloc/geometry/domain.hpp>
#include <polyloc/map/load.hpp>
#include <polyloc/mcl/weighing.hpp>
#include <polyloc/raycast/embree.hpp>

#include <spdlog/spdlog.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <ctime>

namespace polyloc::pipeline {

struct Daemon::Impl final : PipelineSink {
  Daemon& d;
  Mesh map;
  Eigen::AlignedBox3f bounds;
  std::unique_ptr<EmbreeCaster> caster;
  std::unique_ptr<RayCaster> weigh;  // mcl.caster when not embree
  std::unique_ptr<Pipeline> pipe;
  shm::Segment seg;
  std::unique_ptr<InputGate> gate;
  std::unique_ptr<shm::Writer> w_pose, w_vrs, w_tracks, w_health;
  std::unique_ptr<live::LiveView> live;  // null: no live view (port 0, or its port was taken)
  tbb::task_arena arena;
  std::vector<double> cycle_ms;          // ring of the last 1000 cycles
  size_t cycle_next = 0;
  uint64_t cycles = 0;
  uint64_t jumps = 0;                    // of clock: source
  PipelineCounters earlier;              // outputs of the pipelines a time jump replaced
  int64_t last_health_ns = 0;
  uint32_t search_round = 0;             // the global search's last round (0: not searching)
  std::vector<uint8_t> out;              // payload being built

  Impl(Daemon& daemon, shm::Segment s)
      : d(daemon), seg(std::move(s)), arena(d.cfg_.daemon.threads > 0 ? d.cfg_.daemon.threads : tbb::task_arena::automatic) {
    try {
      build();
    } catch (...) {
      seg.stop();  // a start that failed leaves a segment that says so, not "starting; retry"
      throw;
    }
  }

  void build() {
    const PolylocConfig& pc = d.cfg_.polyloc;
    map = loadMesh(pc.map.file, pc.map.load);
    bounds = map.bounds();
    if (const auto& init = d.cfg_.daemon.init)
      if (auto why = domain::checkPlanar(init->pose.x(), init->pose.y(), init->pose.yaw(), map.bounds()))
        throw std::runtime_error(fmt::format("polylocd.init: {} (the map covers {})", *why, domain::describeArea(map.bounds())));
    EmbreeOptions eo;
    eo.threads = d.cfg_.daemon.threads;
    caster = std::make_unique<EmbreeCaster>(map, eo);
    weigh = makeWeighingCaster(map, pc.rig, pc.mcl, d.cfg_.daemon.threads);
    pipe = makePipeline();
    gate = std::make_unique<InputGate>(seg, d.table_, d.cfg_.daemon, [this](int64_t from, int64_t to) { timeJumped(from, to); });
    w_pose = std::make_unique<shm::Writer>(seg, d.table_.pose, true);
    w_vrs = std::make_unique<shm::Writer>(seg, d.table_.vrs, true);
    w_tracks = std::make_unique<shm::Writer>(seg, d.table_.tracks, true);
    w_health = std::make_unique<shm::Writer>(seg, d.table_.health, true);
    startLive();
  }

  // global_search: beside puts the localiser on a thread of its own (pipeline.hpp).
  std::unique_ptr<Pipeline> makePipeline() const {
    PipelineOptions o;
    o.search_beside = d.cfg_.daemon.search_beside;
    o.threads = d.cfg_.daemon.threads;
    o.keep_particles = d.cfg_.daemon.live.port != 0;
    return std::make_unique<Pipeline>(d.cfg_.polyloc, map, *caster, weigh.get(), o);
  }

  // The live view is for people watching: a port in use must not keep the robot from localising.
  void startLive() {
    const live::LiveConfig& lc = d.cfg_.daemon.live;
    if (lc.port == 0) return;
    try {
      live = std::make_unique<live::LiveView>(lc, map, d.cfg_.polyloc.rig, d.table_.inputNames());
      spdlog::info("live view on http://{}:{}/ (Foxglove: ws://{}:{}, docs/live.md)", lc.address, live->port(), lc.address, live->port());
    } catch (const std::exception& e) {
      spdlog::error("{}; polylocd goes on without it", e.what());
    }
  }

  const polyloc_channel_desc& desc(int input) const { return seg.channel(d.table_.inputs[size_t(input)]); }

  // How far a global search is (health flags bit 3 while it runs): each of its rounds, and its end.
  void logSearch(const MclEstimate& e) {
    const size_t most = d.cfg_.polyloc.mcl.global_max_coarse_rounds;
    if (e.global_round > 0)
      spdlog::info("global search: round {} of at most {}, {} particles, {}", e.global_round, most, e.particles, toString(e.status));
    else if (search_round > 0)
      spdlog::info("global search: ended after {} rounds, {} at ({:.2f}, {:.2f}, yaw {:.1f} deg)", search_round,
                   toString(e.status), e.pose.x(), e.pose.y(), rad2deg(e.pose.yaw()));
    search_round = e.global_round;
  }

  // --- outputs (PipelineSink) ---
  void onPose(const MclEstimate& e, const Pose& map_T_odom) override {
    logSearch(e);
    // From the publication of the frame that ended the round (a search's rounds end later).
    const polyloc_pose p = posePayload(e, map_T_odom, clockNs(CLOCK_MONOTONIC) - int64_t(pipe->poseTag()));
    w_pose->write(&p, sizeof p, e.stamp_ns);
    d.live_->update([&](LiveState::Snapshot& s) { s.pose = p; });
    if (live) live->pose(e, map_T_odom, pipe->particles());
  }
  void onVrs(const VirtualScan& v) override {
    const bool enabled = d.live_->collisionAvoidance();
    const uint32_t bytes = vrsPayload(v, enabled, out);
    w_vrs->write(out.data(), bytes, v.stamp_ns);
    d.live_->update([&](LiveState::Snapshot& s) {
      s.vrs = LiveScan{v.stamp_ns, v.angle_min + 0.5f * v.angle_increment, v.angle_increment, v.range_min, v.range_max, v.ranges};
    });
    if (live) live->vrs(v);
  }
  void onTracks(int64_t stamp_ns, const Tracks& t) override {
    const polyloc_tracks p = tracksPayload(stamp_ns, t);
    w_tracks->write(&p, sizeof p, stamp_ns);
    d.live_->update([&](LiveState::Snapshot& s) {
      s.tracks.assign(p.tracks, p.tracks + p.count);
      s.tracks_stamp_ns = stamp_ns;
    });
    if (live) live->tracks(p);
  }

  // Since the start, over every pipeline a time jump replaced.
  PipelineCounters counters() const {
    PipelineCounters c = pipe->counters();
    c.poses += earlier.poses, c.vrs += earlier.vrs, c.tracks += earlier.tracks;
    return c;
  }

  // clock: source moved to another time (SourceClock): the gate dropped what it held of the old
  // time; the pipeline starts again.
  void timeJumped(int64_t from, int64_t to) {
    spdlog::warn("clock: source: the inputs agree on a time {:.3f} s {} the clock's; localisation starts again "
                 "(jump {}; a recording restarted, or a frame stamped wrong was the first)",
                 std::abs(double(static_cast<__int128>(to) - from)) * 1e-9, to > from ? "after" : "before", ++jumps);
    earlier = counters();  // health's counters never go back
    pipe = makePipeline();
  }

  void initialise(int64_t stamp) {
    const auto& init = d.cfg_.daemon.init;
    if (init) {
      Eigen::Matrix<double, 6, 6> cov = Eigen::Matrix<double, 6, 6>::Zero();
      cov.diagonal() << init->sigma_xy * init->sigma_xy, init->sigma_xy * init->sigma_xy, 0.02 * 0.02, 3e-4, 3e-4,
          init->sigma_yaw * init->sigma_yaw;
      if (!pipe->initPose(init->pose, cov, stamp))
        return spdlog::error("polylocd.init refused: {}", pipe->checkPose(init->pose, cov).value_or("?"));
      spdlog::info("localisation starts at ({:.3f}, {:.3f}, yaw {:.1f} deg)", init->pose.x(), init->pose.y(), rad2deg(init->pose.yaw()));
    } else {
      pipe->initGlobal(stamp);
      spdlog::info("global localisation ({} particles)", d.cfg_.polyloc.mcl.global_particles);
    }
  }

  void takeRequests(int64_t stamp) {
    if (auto r = d.live_->takePoseRequest()) {
      if (!pipe->initPose(r->pose, r->covariance, stamp))
        spdlog::warn("pose from the control endpoint refused: {}", pipe->checkPose(r->pose, r->covariance).value_or("?"));
      else
        spdlog::info("pose set by the control endpoint: ({:.3f}, {:.3f}, yaw {:.1f} deg)", r->pose.x(), r->pose.y(), rad2deg(r->pose.yaw()));
    }
    if (d.live_->takeGlobalRequest()) {
      pipe->initGlobal(stamp);
      spdlog::info("global localisation requested by the control endpoint");
    }
    pipe->setVrsEnabled(d.live_->collisionAvoidance());
  }

  void dispatch(const InputGate::Frame& t) {
    const polyloc_channel_desc& c = desc(t.input);
    if (!pipe->initialised()) initialise(t.stamp_ns);
    takeRequests(t.stamp_ns);
    bool ok = true;
    switch (c.kind) {
      case POLYLOC_KIND_ODOMETRY: {
        polyloc_odometry o;
        std::memcpy(&o, t.payload.data(), sizeof o);
        pipe->addOdometry(t.stamp_ns, odometryPose(o));
        break;
      }
      case POLYLOC_KIND_RANGES: {
        const float* r = reinterpret_cast<const float*>(t.payload.data() + offsetof(polyloc_ranges, ranges));
        ok = pipe->addRanges(size_t(c.sensor), t.stamp_ns, {r, c.count}, *this, uint64_t(t.publish_ns));
        if (ok && std::holds_alternative<PlanarScannerSpec>(d.cfg_.polyloc.rig.sensors[size_t(c.sensor)].spec))
          keepScan(size_t(c.sensor), t.stamp_ns, {r, c.count});
        if (ok && live) live->scan(size_t(c.sensor), t.stamp_ns, {r, c.count});
        break;
      }
      case POLYLOC_KIND_DEPTH: {
        polyloc_depth h;
        std::memcpy(&h, t.payload.data(), sizeof h);
        const float* depth = reinterpret_cast<const float*>(t.payload.data() + offsetof(polyloc_depth, data));
        ok = pipe->addDepth(size_t(c.sensor), t.stamp_ns, depth, h.has_amplitude ? depth + size_t(c.width) * c.height : nullptr,
                            *this, uint64_t(t.publish_ns));
        if (ok && live && pipe->vrsEnabled()) live->depth(size_t(c.sensor), t.stamp_ns, pipe->lastDepth());
        break;
      }
      default: ok = false;
    }
    gate->dispatched(t.input, ok);
  }

  // Raw scans of the planar scanners for GETSCANRADIALSCANNER (copied under the lock).
  void keepScan(size_t sensor, int64_t stamp, std::span<const float> r) {
    const auto& spec = std::get<PlanarScannerSpec>(d.cfg_.polyloc.rig.sensors[sensor].spec);
    d.live_->update([&](LiveState::Snapshot& s) {
      auto& ls = s.scans[sensor];
      if (!ls) ls.emplace();
      ls->stamp_ns = stamp;
      ls->angle_min = float(spec.angleMin()), ls->angle_increment = float(spec.resolution_rad);
      ls->range_min = float(spec.range_min), ls->range_max = float(spec.range_max);
      ls->ranges.assign(r.begin(), r.end());
    });
  }

  void publishHealth(bool force) {
    const int64_t mono = clockNs(CLOCK_MONOTONIC);
    if (!force && mono - last_health_ns < int64_t(1e9 / d.cfg_.daemon.health_rate_hz)) return;
    last_health_ns = mono;
    polyloc_health h{};
    h.stamp_ns = clockNs(CLOCK_REALTIME);
    h.cycles = cycles;
    const PipelineCounters pc = counters();
    h.poses = pc.poses, h.vrs = pc.vrs, h.tracks = pc.tracks;
    std::vector<double> c(cycle_ms.begin(), cycle_ms.end());
    if (!c.empty()) {
      std::sort(c.begin(), c.end());
      h.cycle_p50_ms = c[c.size() / 2], h.cycle_p99_ms = c[std::min(c.size() - 1, c.size() * 99 / 100)];
    }
    const std::vector<polyloc_input_health>& health = gate->health(mono);
    h.inputs = uint32_t(health.size());
    for (size_t i = 0; i < health.size(); ++i) {
      h.input[i] = health[i];
      h.input[i].map_fit_permille = 0;  // not measured
      if (health[i].silent) h.flags |= 1u;
    }
    if (pipe->initialised()) {
      const MclEstimate& e = pipe->estimate();
      if (e.status == MclStatus::Lost) h.flags |= 2u;
      if (e.unfit) h.flags |= 4u;
      if (pipe->searching()) h.flags |= 8u;
      for (size_t k = 0; k < e.sensor_fit.size() && k < d.table_.sensor_channel.size(); ++k) {
        const auto it = std::find(d.table_.inputs.begin(), d.table_.inputs.end(), d.table_.sensor_channel[k]);
        if (it != d.table_.inputs.end() && e.sensor_fit[k] >= 0)
          h.input[size_t(it - d.table_.inputs.begin())].map_fit_permille = std::max<uint32_t>(1, uint32_t(std::lround(e.sensor_fit[k] * 1000)));
      }
    }
    w_health->write(&h, sizeof h, h.stamp_ns);
    d.live_->update([&](LiveState::Snapshot& s) { s.health = h; });
    if (live) live->health(h);
  }

  void cycle() {
    const auto t0 = std::chrono::steady_clock::now();
    arena.execute([&] {
      for (const InputGate::Frame& t : gate->ready()) dispatch(t);
    });
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (cycle_ms.size() < 1000) cycle_ms.push_back(ms);
    else cycle_ms[cycle_next++ % 1000] = ms;
    ++cycles;
  }
};

Daemon::Daemon(ServiceConfig config) : cfg_(std::move(config)) {
  table_ = channelTable(cfg_.polyloc.rig, cfg_.polyloc.vrs, cfg_.daemon.slots);
  live_ = std::make_unique<LiveState>(cfg_.polyloc.rig.size());
  live_->setCollisionAvoidance(true);
  shm::Segment seg = shm::Segment::create(cfg_.daemon.instance, table_.specs);
  spdlog::info("segment {} generation {}: {} channels, {:.1f} MiB", shm::segmentName(cfg_.daemon.instance),
               seg.generation(), table_.specs.size(), double(seg.size()) / (1 << 20));
  impl_ = std::make_unique<Impl>(*this, std::move(seg));
}

Daemon::~Daemon() {
  if (impl_ && !ran_) impl_->seg.stop();
}

const Eigen::AlignedBox3f& Daemon::mapBounds() const { return impl_->bounds; }

void Daemon::run(const std::atomic<bool>& stop) {
  Impl& m = *impl_;
  ran_ = true;
  m.seg.ready();
  spdlog::info("ready: rig '{}' ({} sensors), map {} ({} triangles)", cfg_.polyloc.rig.name, cfg_.polyloc.rig.size(),
               cfg_.polyloc.map.file, m.map.numTriangles());
  while (!stop.load(std::memory_order_relaxed)) {
    const uint32_t seen = __atomic_load_n(&m.seg.header().doorbell, __ATOMIC_ACQUIRE);
    const bool read = m.gate->read();
    if (!m.gate->ready().empty()) m.cycle();
    m.pipe->poll(m);  // a search's rounds that ended while no frame came
    if (!read) {
      m.takeRequests(m.gate->now());
      // 20 ms at most: health and silence checks go on, and held frames go when their wait ends.
      if (const int64_t ns = m.gate->sleepNs(monotonicNs()); ns > 0) shm::waitDoorbell(m.seg, seen, ns);
    }
    m.publishHealth(false);
  }
  m.publishHealth(true);
  // The segment stays (STOPPED) under its name: the next start reads its generation and bumps
  // it, which is how clients still attached tell a restart.
  m.seg.stop();
  m.live.reset();  // closes the viewers' connections
  const PipelineCounters pc = m.counters();
  const LocalizerWorker::Counters wc = m.pipe->workerCounters();
  spdlog::info("stopped after {} cycles: {} poses, {} VRS, {} track sets{}", m.cycles, pc.poses, pc.vrs, pc.tracks,
               wc.dropped + wc.cancelled ? fmt::format("; frames queued behind a global search: {} dropped (queue full), {} "
                                                       "dropped by a new start", wc.dropped, wc.cancelled)
                                         : "");
}

}  // namespace polyloc::pipeline
