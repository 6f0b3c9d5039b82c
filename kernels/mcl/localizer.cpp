// Composes the filter: motion model on accumulated odometry (odometry_buffer.hpp), beam model per
// scan, weighed in rounds (round.hpp), blocked particles zeroed, ESS-triggered systematic
// resampling with KLD particle count and augmented-MCL injection, dominant-cluster estimate,
// global phase and sensor resetting (reset_policy.hpp).
#include <polyloc/geometry/domain.hpp>
#include <polyloc/mcl/beam_model.hpp>
#include <polyloc/mcl/sensor_model.hpp>
#include <polyloc/mcl/estimate.hpp>
#include <polyloc/mcl/fit_check.hpp>
#include <polyloc/mcl/free_floor.hpp>
#include <polyloc/mcl/global_search.hpp>
#include <polyloc/mcl/hypotheses.hpp>
#include <polyloc/mcl/localizer.hpp>
#include <polyloc/mcl/motion_model.hpp>
#include <polyloc/mcl/odometry_buffer.hpp>
#include <polyloc/mcl/odometry_noise.hpp>
#include <polyloc/mcl/particles.hpp>
#include <polyloc/mcl/pose_covariance.hpp>
#include <polyloc/mcl/refine.hpp>
#include <polyloc/mcl/resample.hpp>
#include <polyloc/mcl/reset_policy.hpp>
#include <polyloc/mcl/round.hpp>
#include <polyloc/mcl/weighing.hpp>

#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <variant>

namespace polyloc {

namespace {
constexpr uint64_t kResampleStream = 0x524553ULL << 40;
constexpr uint64_t kInjectStream = 0x494E4AULL << 40;
constexpr uint64_t kInitStream = 0x494E49ULL << 40;
constexpr uint64_t kRelocStream = 0x524C43ULL << 40;
constexpr uint64_t kPlantStream = 0x504C54ULL << 40;
constexpr uint64_t kFreshStream = 0x465253ULL << 40;
constexpr uint64_t kScreenStream = 0x534352ULL << 40;
constexpr uint64_t kRecoverStream = 0x524356ULL << 40;
}  // namespace

const char* toString(MclStatus s) {
  switch (s) {
    case MclStatus::Initialising: return "initialising";
    case MclStatus::Tracking: return "tracking";
    case MclStatus::Uncertain: return "uncertain";
    case MclStatus::Lost: return "lost";
  }
  return "?";
}

struct Localizer::Impl {
  Impl(const RayCaster& exact, const Mesh& m, const Rig& r, const MclConfig& cfg, const RayCaster* weigh)
      : caster(weigh ? *weigh : exact), exact(exact), rig(r), config(cfg), floor(exact, m, config), rng(cfg.seed),
        bounds(m.bounds()), policy(config), odo_noise(cfg.motion.adapt), search(caster, exact, m, rig, config) {
    const RayCaster& c = caster;
    for (const auto& s : rig.sensors) beams.push_back(s.beams());
    for (size_t k = 0; k < rig.size(); ++k) level.push_back(rig.isLevelScanner(k));
    const std::vector<uint8_t> weighed = weighedSensors(rig, config);
    // One model instance per name; each sensor points at the one its kind is configured for.
    for (size_t k = 0; k < rig.size(); ++k) {
      const Sensor& s = rig.sensors[k];
      const std::string& name = std::holds_alternative<DepthCameraSpec>(s.spec) ? config.depth_model : config.model;
      if (name == "none" || !weighed[k]) {
        model_of.push_back(nullptr);
        continue;
      }
      auto it = std::find_if(models.begin(), models.end(), [&](const auto& mdl) { return name == mdl->name(); });
      if (it == models.end()) models.push_back(makeSensorModel(name, c, m, rig, config)), it = models.end() - 1;
      model_of.push_back(it->get());
    }
    std::vector<uint8_t> awaited(rig.size());
    for (size_t k = 0; k < rig.size(); ++k) awaited[k] = model_of[k] != nullptr;
    round = UpdateRound(config, std::move(awaited));
    if (config.threads > 0) arena.emplace(config.threads);
  }

  template <class F>
  void run(F&& f) {
    if (arena) arena->execute(f);
    else f();
  }

  void reset(int64_t stamp) {
    est = MclEstimate{};
    map_fit = track_fit = -1;
    sensor_fit.assign(rig.size(), -1.0);
    est.stamp_ns = stamp;
    est.particles = ps.size();
    est.range_bias = range_bias;  // the map's and the odometry's traits outlive a reset
    est.odometry_scale_translation = odo_noise.translationScale();
    est.odometry_scale_rotation = odo_noise.rotationScale();
    round.reset();
    policy.reset();
    beyond_radius = false;
    std::fill(w_slow.begin(), w_slow.end(), 0.0);
    std::fill(w_fast.begin(), w_fast.end(), 0.0);
    odom_at_update = odom_at_predict = odom_at_round = scan_odom = odometry.at(stamp);
    last_refined.valid = false;
    pose_cov.invalidate();
    initialised = true;
    if (config.dof == 3) floor.snapToFloor(ps);
    refreshEstimate(MclStatus::Initialising);
  }

  void refreshEstimate(std::optional<MclStatus> forced) {
    const double cell = std::max(2 * config.kld_bin_xy, 0.25);
    ClusterEstimate c = dominantCluster(ps, cell);
    est.pose = c.pose;
    est.covariance = c.covariance;
    est.particles = ps.size();
    est.status = ps.size() == 0 ? MclStatus::Lost : forced ? *forced : statusOf(c, config);
  }

  void resample() {
    const size_t N = ps.size();
    const uint64_t stream = kResampleStream + 2 * step;
    std::vector<size_t> idx = systematicResample(ps.logw, N, rng, stream);
    if (config.kld) {
      const size_t n = kldParticleCount(occupiedBins(ps, idx, config), config);
      if (n != N) idx = systematicResample(ps.logw, n, rng, stream + 1);
    }
    ps = gatherParticles(ps, idx);
    ++counters.resamples;
    // Augmented MCL: inject uniform free-space particles when the short-term likelihood falls
    // below the long-term one (kidnapping, divergence).
    const double p_inject = est.contradicted ? injectProbability() : 0.0;
    if (p_inject > 0) {
      std::vector<size_t> slots;
      for (size_t j = 0; j < ps.size(); ++j)
        if (rng.uniform(kInjectStream + step, j, 0) < p_inject) slots.push_back(j);
      const std::vector<Pose> fresh = floor.sampleFree(slots.size(), rng, kInjectStream + step);
      for (size_t k = 0; k < fresh.size(); ++k) setParticle(ps, slots[k], fresh[k]);
      counters.injected += fresh.size();
    }
  }

  // config.hypotheses.fresh uniform free-floor particles appended, at the mean weight.
  void addFresh() {
    const std::vector<Pose> poses = floor.sampleFree(config.hypotheses.fresh, rng, kFreshStream + step);
    if (poses.empty()) return;
    normalizeLogWeights(ps.logw);
    const size_t n0 = ps.size();
    resizeParticles(ps, n0 + poses.size());
    const double w = -std::log(double(n0 + poses.size()));
    const double shift = -std::log(double(n0 + poses.size()) / double(n0));  // old particles keep their relative weights
    for (size_t i = 0; i < n0; ++i) ps.logw[i] += shift;
    for (size_t k = 0; k < poses.size(); ++k) setParticle(ps, n0 + k, poses[k]), ps.logw[n0 + k] = w;
    counters.injected += poses.size();
  }

  // Global particles uniform over the free floor, equal weights.
  void drawUniform(uint64_t stream) {
    search.restart();
    const std::vector<Pose> poses = floor.sampleFree(config.global_particles, rng, stream);
    resizeParticles(ps, poses.size());
    for (size_t i = 0; i < poses.size(); ++i) setParticle(ps, i, poses[i]), ps.logw[i] = -std::log(double(poses.size()));
  }

  // Of the sensor weighed last: each sensor has its own likelihood level (a tilted scanner on
  // the floor fits differently from a horizontal one), so mixing them in one average would make
  // w_fast swing with the order of sensors and inject particles while tracking well.
  double injectProbability() const {
    if (config.alpha_slow <= 0 || config.alpha_fast <= 0 || current >= w_slow.size() ||
        w_slow[current] <= 0)
      return 0.0;
    return std::clamp(1.0 - w_fast[current] / w_slow[current], 0.0, 0.5);
  }

  // Weighs one sensor's frame into the particle weights. Resampling waits for the end of the
  // round (closeRound), so the survivors are chosen on the fused evidence of every sensor, not on
  // one sensor alone (a scanner tilted onto the floor fits any particle on flat floor equally).
  bool update(size_t sensor, int64_t stamp, std::span<const float> ranges) {
    // Motion since the last prediction, applied lazily: the noise then scales with the whole
    // step, not with the number of odometry messages.
    const Pose delta = odom_at_predict.inverse() * scan_odom;
    ++step;
    if (!delta.isApprox(Pose(), 1e-12)) {
      // After a round whose scans contradicted the estimate the odometry may have slipped or
      // jumped (a real log's ODOM lines are 20 deg off now and then): the next prediction
      // spreads wider, so that some particles follow where the scans are.
      MotionNoise noise = config.motion.adapt.enabled ? odo_noise.scaled(config.motion) : config.motion;
      if (est.contradicted)
        for (double* a : {&noise.alpha1, &noise.alpha2, &noise.alpha3, &noise.alpha4}) *a *= config.motion.recovery_scale;
      applyMotion(ps, delta, noise, config.dof, rng, step);
    }
    odom_at_predict = scan_odom;
    if (config.dof == 3) floor.snapToFloor(ps);
    loglik.assign(ps.size(), 0.0);
    SensorModel& model = *model_of[sensor];
    const bool coarse = (est.status != MclStatus::Tracking && !beyond_radius) || policy.coarse();
    const SensorFrame frame{sensor, stamp, ranges, scan_odom, step, coarse};
    const size_t used = model.weigh(ps, frame, loglik);
    if (used == 0) return false;
    // Mean per-beam likelihood (geometric) of the particles: for augmented MCL and "lost".
    // Untempered (log_scale divided out): tempering must not hide a kidnapping.
    double w_avg = 0, best = -std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < ps.size(); ++i) {
      const double l = loglik[i] / (double(used) * model.logScale());
      w_avg += std::exp(l), best = std::max(best, l);
      ps.logw[i] += loglik[i];
    }
    w_avg /= double(std::max<size_t>(ps.size(), 1));
    if (w_slow.size() < rig.size()) w_slow.resize(rig.size(), 0.0), w_fast.resize(rig.size(), 0.0);
    current = sensor;
    double& slow = w_slow[sensor];
    double& fast = w_fast[sensor];
    // Only fine (tracking) weightings feed the averages: a coarse one has another likelihood
    // level, and mixing them would read as a kidnapping each time the filter turns uncertain.
    if (!frame.coarse) {
      if (slow == 0) slow = fast = w_avg;
      slow += config.alpha_slow * (w_avg - slow);
      fast += config.alpha_fast * (w_avg - fast);
    }

    {
      const BlockedResult b = floor.zeroBlocked(ps, config.blocked_max_mass);
      counters.particles_blocked += b.zeroed;
      counters.blocked_ignored += b.ignored;
    }
    if (!normalizeLogWeights(ps.logw)) ++counters.weights_collapsed, ++round.collapsed;
    // No particle explains the scan better than the non-hit parts of the mixture.
    round.lost += best < model.unexplainedLogLikelihood(sensor);
    ++round.sensors;
    // Kept for the refinement, the global hypotheses and the fit check; raw ToF frames only when
    // asked (flying pixels and multipath bias a fit).
    if (config.refine.depth_cameras || !std::holds_alternative<DepthCameraSpec>(rig.sensors[sensor].spec))
      round.keep(sensor, ranges, scan_odom);
    round.inject_due = std::max(round.inject_due, injectProbability());
    ++counters.updates;
    est.updates = counters.updates;
    round.stamp = stamp;
    return true;
  }

  // Ends a round of sensor updates: the estimate, then resampling when the weights have
  // degenerated or injection is due (a lost cloud is flat, high ESS, and would never resample,
  // so it would never get fresh particles).
  void closeRound() {
    if (round.sensors == 0) return;
    const uint64_t reloc_at_round = counters.relocalizations;
    est.stamp_ns = round.stamp;  // the particles are at the odometry of the last frame weighed
    const bool global_round = policy.beginRound();
    est.global_round = global_round ? uint32_t(policy.globalRounds()) : 0;
    // Only right after a uniform prior: planting refined modes while tracking through a crowd
    // (uncertain, weighed coarse) moves a good cloud onto fits that people distort.
    ambiguous = false;
    best_hypothesis.reset();
    const bool planted = global_round && config.hypotheses.count > 0 && plantRefinedModes();
    est.ess = effectiveSampleSize(ps.logw);
    // Lost when most sensors of the round are explained by no particle (one sensor alone may be
    // blinded by a person standing in front of it).
    const bool lost = round.collapsed > 0 || 2 * round.lost > round.sensors;
    const MclEstimate before = est;
    // The filter's view of the last round: tracking, also when only tracking_radius published it
    // uncertain (a promise to the controller; the weighting, the jump and innovation checks go on).
    const bool was_tracking = before.status == MclStatus::Tracking || beyond_radius;
    beyond_radius = false;
    refreshEstimate(lost ? std::optional<MclStatus>(MclStatus::Lost) : std::nullopt);
    // While the global search goes on its leading place is the estimate, whatever the cloud says.
    if (best_hypothesis) est.pose = *best_hypothesis;
    // Where the last estimate would be now by odometry; a tracked estimate far from it was taken
    // over by injected particles.
    const Pose predicted = before.pose * (odom_at_round.inverse() * odom_at_predict);
    odom_at_round_prev = odom_at_round;
    odom_at_round = odom_at_predict;
    bool jumped = policy.jumped(was_tracking, global_round, est.pose, predicted);
    if (config.refine.enabled) refineEstimate(predictionCovariance(before));
    checkEstimateFit(global_round);
    learnOdometryNoise();
    trackCovariance(before, global_round, was_tracking);
    est.recovered = false;
    // The estimate could not be pinned against the map, or nothing explains the scans: search
    // near the prediction. A round that is only contradicted (beams seen through the map) but
    // pinned is left alone: maps with phantom obstacles (an end-point map keeps every person the
    // mapping run saw) contradict the right place now and then.
    jumped = jumped && est.contradicted;  // a jump to a place the scans fit is the filter doing its job
    // Unpinned only where refinement runs (refine.enabled): with it off no round is refined, and
    // recovery fired on every one (MCL alone: 1,540 recoveries in 1,541 rounds, status uncertain).
    const bool unpinned = config.refine.enabled && !est.refined;
    const bool troubled = lost || unpinned || jumped;
    if (!global_round && troubled && before.status != MclStatus::Initialising) recoverLocally(before, predicted, lost);
    // A jump into a contradicted place starts a global search only when no place near the
    // prediction fits: a sharp turn on bad odometry moves the cloud off, and the place it left
    // is found again locally (real logs, 10 %/2 deg per m drift: a global reset from a good
    // track cost 27 m for five rounds).
    if (est.recovered) jumped = false;
    flagJump(was_tracking, predicted);
    policy.extendGlobal(global_round, est.contradicted, est.refined, ambiguous);
    if (policy.relocalize(jumped, est.contradicted, est.refined)) {
      drawUniform(kRelocStream + step);
      policy.startGlobal();
      w_fast = w_slow;  // no injection into the fresh prior until tracking weighs again
      ++counters.relocalizations;
      refreshEstimate(MclStatus::Lost);
    } else if (planted || est.recovered || est.ess < config.resample_ess * double(ps.size()) ||
               (est.contradicted && round.inject_due > 0.05)) {
      resample();
    }
    // Global localisation: fresh uniform particles each coarse round, so that places the prior
    // missed can still become modes (and be refined) while the robot moves.
    if (global_round && policy.coarse() && config.hypotheses.count > 0 && config.hypotheses.fresh > 0 &&
        counters.relocalizations == reloc_at_round)
      addFresh();
    beyond_radius = beyond_radius && est.status == MclStatus::Tracking;
    if (beyond_radius) est.status = MclStatus::Uncertain;
    // Never tracking before the global search has committed: a place the rounds so far cannot
    // tell from another is a guess (real logs: infinite-corridor published tracking 239 m off
    // in the second round after a uniform prior).
    if (global_round && (policy.coarse() || ambiguous) && est.status == MclStatus::Tracking)
      est.status = MclStatus::Uncertain;
    est.particles = ps.size();
    round.clear();
  }

  // The round's frames, relative to the odometry of the last weighed frame (the particles' time).
  std::vector<RefineScan> roundScans() const { return round.scans(odom_at_predict); }

  // Global localisation (hypotheses.hpp): the cloud's best distinct modes refined against the
  // round's frames; those that fit are planted back as tight clouds. True when any was planted.
  bool plantRefinedModes() {
    const std::vector<RefineScan> scans = roundScans();
    if (scans.empty()) return false;
    GlobalRound g = search.round(scans, ps, odom_at_predict, floor, rng, kScreenStream);
    // Several places fit alike: the robot must move on before the filter commits.
    ambiguous = g.ambiguous;
    best_hypothesis = g.best;
    const std::vector<Hypothesis>& hyps = g.hypotheses;
    const size_t n = plantHypotheses(ps, hyps, config.hypotheses, rng, kPlantStream + step);
    if (n == 0) return false;
    counters.hypotheses += hyps.size();
    if (config.dof == 3) floor.snapToFloor(ps);
    normalizeLogWeights(ps.logw);
    est.ess = effectiveSampleSize(ps.logw);
    return true;
  }

  // Local recovery (mcl.recovery): the round doubts the estimate; places near the prediction
  // (the last estimate moved by odometry) at the headings the prediction allows are screened,
  // the best refined with the cloud's modes, and those that fit planted.
  void recoverLocally(const MclEstimate& before, const Pose& predicted, bool lost_round) {
    if (!config.recovery || config.hypotheses.count == 0) return;
    const std::vector<RefineScan> scans = roundScans();
    if (scans.empty()) return;
    const Eigen::Matrix3d cov = predictionCovariance(before);
    const double radius = std::clamp(config.recovery_sigmas * maxPositionStd(cov), config.recovery_min_radius, config.recovery_max_radius);
    // When nothing explains the scans the heading may be anything: every heading is screened.
    const double window = lost_round ? M_PI : std::clamp(config.recovery_sigmas * std::sqrt(cov(2, 2)), config.recovery_min_heading, M_PI);
    std::vector<Pose> positions;
    const int n = int(std::ceil(radius / config.recovery_step));
    for (int i = -n; i <= n; ++i)
      for (int j = -n; j <= n; ++j) {
        const double dx = i * config.recovery_step, dy = j * config.recovery_step;
        if (dx * dx + dy * dy <= radius * radius) positions.push_back(Pose::planar(dx, dy, 0) * predicted.planarProjection());
      }
    std::vector<Hypothesis> hyps = search.fittingModes(scans, ps, positions, window, config.fit.past_share);
    // The cloud's modes are refined too: those outside the prediction's reach are not local.
    std::erase_if(hyps, [&](const Hypothesis& h) {
      return (h.pose.translation() - predicted.translation()).head<2>().norm() > radius + config.hypotheses.max_correction ||
             std::abs(angleDiff(h.pose.yaw(), predicted.yaw())) > window + config.hypotheses.max_correction_yaw;
    });
    // A place that explains far fewer beams than the track did is no recovery: after a
    // kidnapping some place near the old one passes the fit check at another heading (the lab:
    // 44 % of the beams explained where the track had explained 70 %), and planting it there
    // kept the filter from searching globally.
    if (track_fit > 0)
      std::erase_if(hyps, [&](const Hypothesis& h) {
        return checkFit(exact, rig, scans, h.pose, config.fit.tolerance, config.fit.beams_per_scan).explainedShare() <
               config.recovery_min_fit * track_fit;
      });
    if (hyps.empty()) return;
    // Planted at the weight of the heaviest particle, whatever the prediction says: recovery is
    // for steps the motion model did not expect (weighed by the prediction's density, the right
    // heading 44 deg off a wrong prediction started 1e4 times lighter and lost).
    if (plantHypotheses(ps, hyps, config.hypotheses, rng, kRecoverStream + step) == 0) return;
    if (config.dof == 3) floor.snapToFloor(ps);
    normalizeLogWeights(ps.logw);
    ++counters.recoveries;
    est.recovered = true;
    // The estimate stays this round's: a place the recovery found is not confirmed until the
    // next rounds weigh it against the rest of the cloud (along a corridor the nearest fit was
    // 1.6 m off while the cloud's mean was 0.2 m off).
    if (est.status == MclStatus::Tracking) est.status = MclStatus::Uncertain;
  }

  // The published covariance (pose_covariance.hpp): the tracked one in x, y, yaw (the cloud's
  // spread added: several modes), z, roll, pitch as the cloud and the fit say; a fit that fails
  // the innovation gate against the prediction (the fit or the odometry is wrong, the round
  // cannot tell which: real logs, 10 % drift, a fit 0.5 m along a corridor from the truth, 7 std
  // from the prediction, was published as tracking) or a tracked std beyond uncertain_xy /
  // uncertain_yaw is not tracking.
  void trackCovariance(const MclEstimate& before, bool global_round, bool was_tracking) {
    est.inconsistent = false;
    const Eigen::Matrix3d cloud = planarCovariance(est.covariance);
    const Eigen::Matrix3d fit = planarCovariance(refine_cov);
    // With refinement off (MCL alone) the cloud is the round's measurement: fused like a fit, not
    // added on top (with nothing fused the carried covariance only grew: tracking 0 % of rounds).
    const bool cloud_measures = !config.refine.enabled;
    if (global_round || before.status == MclStatus::Initialising || !pose_cov.valid()) {
      pose_cov.restart(cloud + (est.refined ? fit : Eigen::Matrix3d::Zero()));
    } else {
      const Eigen::Matrix3d* measured = est.refined ? &fit : cloud_measures ? &cloud : nullptr;
      const double nis = pose_cov.update(before.pose, odom_at_round_prev.inverse() * odom_at_predict, odo_noise.scaled(config.motion),
                                         est.pose, measured,
                                         {config.innovation_floor_xy, config.innovation_floor_xy, config.innovation_floor_yaw});
      est.inconsistent = config.innovation_gate > 0 && was_tracking && nis > config.innovation_gate;
      counters.inconsistent += est.inconsistent;
      if (!cloud_measures) pose_cov.restart(pose_cov.covariance() + cloud);
    }
    if (!pose_cov.valid()) pose_cov.restart(cloud);
    if (est.status == MclStatus::Lost) pose_cov.invalidate();
    if (est.refined) est.covariance += refine_cov;
    setPlanarCovariance(est.covariance, pose_cov.covariance());
    const Eigen::Matrix3d& p = pose_cov.covariance();
    if (est.status == MclStatus::Tracking &&
        (maxPositionStd(p) > config.uncertain_xy || std::sqrt(p(2, 2)) > config.uncertain_yaw || est.inconsistent))
      est.status = MclStatus::Uncertain;
    // 3.035 std: the radius that holds a 2-D Gaussian at 99 % when both axes have the worst std.
    // Applied when the round ends (closeRound), to the published status only.
    beyond_radius = config.tracking_radius > 0 && 3.035 * maxPositionStd(p) > config.tracking_radius;
  }

  // The prediction's uncertainty (x, y, yaw): the last estimate's and the motion since the last
  // round, with the noise the scans found in the odometry.
  Eigen::Matrix3d predictionCovariance(const MclEstimate& before) const {
    Eigen::Matrix3d cov = motionCovariance(odom_at_round_prev.inverse() * odom_at_predict, odo_noise.scaled(config.motion));
    cov.topLeftCorner<2, 2>() += before.covariance.topLeftCorner<2, 2>();
    cov(2, 2) += before.covariance(5, 5);
    return cov;
  }

  // The scans' verdict on the odometry: consecutive refined estimates against the odometry
  // between them (odometry_noise.hpp).
  void learnOdometryNoise() {
    // The range bias follows what the refinements found, where the scans fit the map.
    if (config.range_bias && est.refined && !est.contradicted)
      range_bias = std::clamp(range_bias + config.range_bias_gain * bias_step, -config.range_bias_max, config.range_bias_max);
    est.range_bias = range_bias;
    if (!est.refined || est.contradicted) {
      if (est.contradicted) last_refined.valid = false;
      return;
    }
    if (last_refined.valid && config.motion.adapt.enabled)
      odo_noise.addPair(last_refined.pose, last_refined.cov, est.pose, refine_cov,
                        last_refined.odom.inverse() * odom_at_predict, config.motion);
    last_refined = {est.pose, refine_cov, odom_at_predict, true};
    est.odometry_scale_translation = odo_noise.translationScale();
    est.odometry_scale_rotation = odo_noise.rotationScale();
  }

  // A tracked pose that moved more than mcl.max_jump beyond the odometry since the last one
  // jumped: this round says so in its status.
  void flagJump(bool was_tracking, const Pose& predicted) {
    est.jumped = false;
    if (config.max_jump <= 0 || !was_tracking) return;
    if ((est.pose.translation() - predicted.translation()).head<2>().norm() <= config.max_jump) return;
    est.jumped = true;
    ++counters.jumps;
    if (est.status == MclStatus::Tracking) est.status = MclStatus::Uncertain;
  }

  // The round's frames cast from the estimate in the exact map (fit_check.hpp): do they see
  // through its walls? A contradicted estimate is uncertain at best. Beams past surfaces behind
  // (mcl.fit.past_share) spare a place the track holds, not one the global search offers: that
  // must fit every beam before the filter commits (a far place needs the stronger evidence).
  void checkEstimateFit(bool global_round) {
    const double past_share = global_round ? 2.0 : config.fit.past_share;
    const std::vector<RefineScan> scans = roundScans();
    ScanFit fit;
    const auto smooth = [&](double& v, double x) { v = v < 0 ? x : v + config.fit.smoothing * (x - v); };
    for (const RefineScan& s : scans) {  // per frame: the fit per sensor too
      const ScanFit f = checkFit(exact, rig, {&s, 1}, est.pose, config.fit.tolerance, config.fit.beams_per_scan, past_share);
      fit.beams += f.beams, fit.explained += f.explained, fit.shorter += f.shorter, fit.longer += f.longer, fit.past_surface += f.past_surface;
      if (f.beams > 0 && s.sensor < sensor_fit.size()) smooth(sensor_fit[s.sensor], f.explainedShare());
    }
    if (fit.beams > 0) smooth(map_fit, fit.explainedShare());
    est.seen_through = fit.seenThrough();
    est.contradicted = fit.beams > 0 && est.seen_through > config.fit.max_seen_through;
    // The fit of the rounds the track was sure of: what a recovered place must come close to.
    if (fit.beams > 0 && est.refined && !est.contradicted && est.status == MclStatus::Tracking)
      smooth(track_fit, fit.explainedShare());
    est.map_fit = map_fit;
    est.sensor_fit = sensor_fit;
    est.unfit = map_fit >= 0 && map_fit < config.fit.min_explained;
    if (est.unfit) {
      ++counters.unfit;
      if (est.status == MclStatus::Tracking) est.status = MclStatus::Uncertain;
    }
    if (!est.contradicted) return;
    ++counters.contradicted;
    if (est.status == MclStatus::Tracking) est.status = MclStatus::Uncertain;
  }

  // The estimate refined against the mesh with the round's frames (refine.hpp), while tracking:
  // a wrong-mode or spread cloud is left to the filter. The particles are not moved: the
  // refinement is an output, the filter stays a filter.
  void refineEstimate(const Eigen::Matrix3d& prior) {
    est.refined = false;
    bias_step = 0;
    if (est.status != MclStatus::Tracking) return;
    const std::vector<RefineScan> scans = roundScans();
    if (scans.empty()) return;
    RefineConfig rc = config.refine;
    rc.range_bias = config.range_bias;
    // The search covers the prediction's uncertainty (a collapsed cloud says nothing about it):
    // long steps on bad odometry leave the estimate decimetres off, beyond a fixed window.
    if (rc.search_xy > 0 || rc.search_yaw > 0) {
      rc.search_xy = std::clamp(rc.search_sigmas * maxPositionStd(prior), rc.search_xy, std::max(rc.search_xy, rc.max_search_xy));
      rc.search_yaw = std::clamp(rc.search_sigmas * std::sqrt(prior(2, 2)), rc.search_yaw, std::max(rc.search_yaw, rc.max_search_yaw));
      rc.max_correction = std::max(rc.max_correction, rc.search_xy + config.refine.max_correction);
      rc.max_correction_yaw = std::max(rc.max_correction_yaw, rc.search_yaw + config.refine.max_correction_yaw);
    }
    const RefineResult r = refinePose(caster, rig, scans, est.pose, config.refine.dof ? config.refine.dof : config.dof, rc,
                                      config.refine.search_spread ? config.effective_beams : 0.0);
    if (!r.accepted) return void(++counters.refinements_refused);
    bias_step = r.range_bias;
    est.pose = r.pose;
    // The cloud of a well-observed pose collapses to copies of a few particles (its spread can
    // read 1e-10 m); the fit's covariance says how well the scans pin the refined pose. Both
    // together are what a controller should be told. The fit treats its beams as independent;
    // they are not (a map centimetres off, a person bias neighbours alike), so it counts as
    // effective_beams of them, as the weighting does (real logs: NEES ~10 without).
    const double dependent = config.effective_beams > 0 ? std::max(1.0, double(r.correspondences) / config.effective_beams) : 1.0;
    refine_cov = dependent * r.covariance;
    // Where the scans leave the pose free (along a corridor) the search's likelihood is flat or
    // has several minima, which the Hessian of the one Gauss-Newton found does not show.
    setPlanarCovariance(refine_cov, planarCovariance(refine_cov) + r.search_spread);
    est.refined = true;
    ++counters.refinements;
  }

  const RayCaster& caster;  // the sensor models' and the refinement's (mcl.caster)
  const RayCaster& exact;   // the mesh itself (Embree): floor, free space, the fit check
  Rig rig;
  MclConfig config;
  FreeFloor floor;
  CounterRng rng;
  double map_fit = -1;              // smoothed over rounds (mcl.fit); -1: not measured since the reset
  double track_fit = -1;            // ... over the refined, uncontradicted, tracking rounds only
  std::vector<double> sensor_fit;   // per rig sensor
  Eigen::AlignedBox3f bounds;  // the map's: poses beyond it plus domain::kMapMargin are refused
  std::vector<BeamSet> beams;
  std::vector<std::unique_ptr<SensorModel>> models;
  std::vector<SensorModel*> model_of;  // per rig sensor; null: its frames are not used
  std::vector<double> loglik;          // per particle, reused between updates
  std::optional<tbb::task_arena> arena;
  ParticleSet ps;
  MclCounters counters;
  MclEstimate est;
  bool initialised = false;
  OdometryBuffer odometry;
  Pose odom_at_predict, odom_at_update;
  Pose odom_at_round;  // odometry at the last round's estimate (relocalize_jump)
  Pose odom_at_round_prev;  // ... and at the one before (the step local recovery searches around)
  struct RefinedAt {
    Pose pose;
    Eigen::Matrix<double, 6, 6> cov = Eigen::Matrix<double, 6, 6>::Zero();
    Pose odom;
    bool valid = false;
  } last_refined;          // the last refined, uncontradicted estimate
  Eigen::Matrix<double, 6, 6> refine_cov = Eigen::Matrix<double, 6, 6>::Zero();  // of this round's refinement
  PoseCovariance pose_cov;  // the published pose's (x, y, yaw), carried over rounds
  double range_bias = 0;           // m, taken off the level scanners' ranges (mcl.range_bias)
  double bias_step = 0;            // what this round's refinement found on top of it
  std::vector<uint8_t> level;      // per rig sensor: a level scanner
  std::vector<float> biased;       // a frame's ranges less the bias
  Pose scan_odom;  // odometry interpolated to the stamp of the scan being weighed
  UpdateRound round;
  ResetPolicy policy;
  OdometryNoise odo_noise;  // the alphas' scales the scans found (mcl.motion.adapt)
  uint64_t step = 0;
  std::vector<double> w_slow, w_fast;  // augmented MCL likelihood averages, per rig sensor
  size_t current = 0;                  // sensor of the last update
  GlobalSearch search;       // global localisation's places (and local recovery's candidates)
  // The last round was published uncertain by mcl.tracking_radius alone: the filter goes on as tracking.
  bool beyond_radius = false;
  bool ambiguous = false;    // the round's refined modes (global localisation) found several places
  std::optional<Pose> best_hypothesis;  // the best tracked place of this global round
};

Localizer::Localizer(const RayCaster& caster, const Mesh& map, const Rig& rig, const MclConfig& config,
                     const RayCaster* weigh)
    : impl_(std::make_unique<Impl>(caster, map, rig, config, weigh)) {}
Localizer::~Localizer() = default;

std::optional<std::string> Localizer::checkPose(const Pose& pose, const Eigen::Matrix<double, 6, 6>& cov) const {
  if (auto why = domain::checkPose(pose, impl_->bounds)) return why;
  if (!cov.allFinite()) return std::string("covariance has a non-finite entry");
  static const char* kNames[] = {"sigma x", "sigma y", "sigma z", "sigma roll", "sigma pitch", "sigma yaw"};
  for (int k = 0; k < 6; ++k) {
    const double v = cov(k, k);
    if (auto why = domain::checkSpread(kNames[k], v < 0 ? v : std::sqrt(v),
                                       k < 3 ? domain::kMaxPositionSigma : domain::kMaxAngle))
      return why;
  }
  return std::nullopt;
}

bool Localizer::initPose(const Pose& pose, const Eigen::Matrix<double, 6, 6>& cov, int64_t stamp) {
  Impl& d = *impl_;
  if (checkPose(pose, cov)) return ++d.counters.poses_rejected, false;
  d.run([&] {
    // Draw from N(pose, cov) in (x y z roll pitch yaw); a covariance that is not positive
    // definite falls back to its diagonal.
    Eigen::Matrix<double, 6, 6> L = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::LLT<Eigen::Matrix<double, 6, 6>> llt(cov);
    if (cov.allFinite() && llt.info() == Eigen::Success) L = llt.matrixL();
    else
      for (int k = 0; k < 6; ++k) L(k, k) = std::isfinite(cov(k, k)) ? std::sqrt(std::abs(cov(k, k))) : 0.0;
    const Pose& p0 = pose;
    const size_t n = std::max<size_t>(d.config.particles, 1);
    resizeParticles(d.ps, n);
    for (size_t i = 0; i < n; ++i) {
      Eigen::Matrix<double, 6, 1> g;
      for (int k = 0; k < 6; ++k) g[k] = d.rng.normal(kInitStream + uint64_t(stamp), i, k);
      const Eigen::Matrix<double, 6, 1> e = L * g;
      setParticle(d.ps, i, Pose::fromXYZRPY(p0.x() + e[0], p0.y() + e[1], p0.z() + e[2], p0.roll() + e[3],
                                            p0.pitch() + e[4], p0.yaw() + e[5]));
      d.ps.logw[i] = -std::log(double(n));
    }
    d.reset(stamp);
  });
  return true;
}

void Localizer::initGlobal(int64_t stamp) {
  Impl& d = *impl_;
  d.run([&] {
    d.drawUniform(kInitStream + uint64_t(stamp));
    d.reset(stamp);
    d.policy.startGlobal();
  });
}

void Localizer::addOdometry(int64_t stamp, const Pose& odom_T_base) {
  Impl& d = *impl_;
  ++d.counters.odometry;
  switch (d.odometry.add(stamp, odom_T_base)) {
    case OdometryBuffer::Added::Invalid: ++d.counters.odometry_invalid; break;
    case OdometryBuffer::Added::OutOfOrder: ++d.counters.odometry_out_of_order; break;
    case OdometryBuffer::Added::First:
      // The first message is the reference: no motion before it.
      d.odom_at_predict = d.odom_at_update = odom_T_base;
      break;
    case OdometryBuffer::Added::AfterGap: ++d.counters.odometry_gaps; break;  // still used: the delta spans the gap
    case OdometryBuffer::Added::Accepted: break;
  }
}

Pose Localizer::odometryAt(int64_t stamp_ns) const { return impl_->odometry.at(stamp_ns); }

bool Localizer::addScan(size_t sensor, int64_t stamp, std::span<const float> ranges) {
  Impl& d = *impl_;
  ++d.counters.scans;
  if (!d.initialised || sensor >= d.rig.size() || ranges.size() != d.beams[sensor].size() ||
      d.round.stale(sensor, stamp) || d.ps.size() == 0)
    return ++d.counters.scans_rejected, false;
  if (BeamSensorModel::selectBeams(d.beams[sensor], ranges, 1).empty()) return ++d.counters.scans_rejected, false;
  if (!d.model_of[sensor]) return false;  // not weighed: depth_model none, or not in mcl.sensors
  d.round.heard(sensor, stamp);
  d.scan_odom = d.odometry.at(stamp);
  bool closed = false;
  if (d.round.timedOut(stamp)) {
    d.run([&] { d.closeRound(); });
    closed = true;
    d.round.abandon();
  }
  const Pose moved = d.odom_at_update.inverse() * d.scan_odom;
  if (d.round.due(moved)) {
    d.round.start(sensor, stamp);
    d.odom_at_update = d.scan_odom;
  }
  if (!d.round.take(sensor)) return closed;
  // The map's proudness (mcl.range_bias) taken off a level scanner's ranges before anything
  // weighs or keeps them.
  if (d.range_bias != 0 && d.level[sensor]) {
    subtractRangeBias(ranges, d.range_bias, d.beams[sensor].range_max, d.biased);
    ranges = d.biased;
  }
  d.run([&] {
    d.update(sensor, stamp, ranges);
    if (d.round.complete()) d.closeRound(), closed = true;
  });
  return closed;
}

MclEstimate Localizer::estimate() const { return impl_->est; }
bool Localizer::searching() const { return impl_->initialised && impl_->policy.coarse(); }
const ParticleSet& Localizer::particles() const { return impl_->ps; }
const MclCounters& Localizer::counters() const { return impl_->counters; }
const MclConfig& Localizer::config() const { return impl_->config; }

}  // namespace polyloc
