#include "reloc/outcome.hpp"

#include <nlohmann/json.hpp>

#include <stdexcept>

namespace polyloc::reloc {
namespace {

using nlohmann::json;

json poseJson(const Pose& p) {
  const auto& q = p.rotation();
  return json::array({p.x(), p.y(), p.z(), q.w(), q.x(), q.y(), q.z()});
}
Pose poseFrom(const json& j) {
  return Pose(Eigen::Quaterniond(j[3].get<double>(), j[4].get<double>(), j[5].get<double>(), j[6].get<double>()),
              {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()});
}
json points(const std::vector<Eigen::Vector2f>& v) {
  json a = json::array();
  for (const auto& p : v) a.push_back(p.x()), a.push_back(p.y());
  return a;
}
std::vector<Eigen::Vector2f> pointsFrom(const json& a) {
  std::vector<Eigen::Vector2f> v;
  for (size_t i = 0; i + 1 < a.size(); i += 2) v.emplace_back(a[i].get<float>(), a[i + 1].get<float>());
  return v;
}

json resultJson(const JobResult& r) {
  json frames = json::array();
  for (const auto& f : r.frames) {
    json cov = json::array();
    for (int i = 0; i < 36; ++i) cov.push_back(f.covariance.data()[i]);
    frames.push_back({{"t", f.stamp_ns}, {"p", poseJson(f.pose)}, {"c", cov}, {"s", int(f.status)}, {"e", f.ess},
                      {"n", f.particles}, {"v", f.seen_through}, {"r", f.refined}, {"f", f.map_fit}});
  }
  json truth = json::array();
  for (const auto& t : r.truth) truth.push_back({t.stamp_ns, poseJson(t.pose)});
  json clouds = json::array();
  for (const auto& c : r.plot.clouds)
    clouds.push_back({{"t", c.t_s}, {"u", c.update}, {"p", poseJson(c.estimate)}, {"x", points(c.particles)}});
  return {{"input", r.input}, {"format", r.format}, {"init_mode", r.init_mode}, {"init_ns", r.init_ns},
          {"keep_from_ns", r.keep_from_ns}, {"keep_to_ns", r.keep_to_ns}, {"frames", frames}, {"truth", truth},
          {"truth_from_stream", r.truth_from_stream}, {"counters", r.counters}, {"updates", r.updates},
          {"final_particles", r.final_particles}, {"final_status", int(r.final_status)},
          {"final_pose", poseJson(r.final_pose)}, {"filter_s", r.filter_s}, {"wall_s", r.wall_s},
          {"path", points(r.plot.estimate_path)}, {"clouds", clouds}, {"warnings", r.warnings}};
}

JobResult resultFrom(const json& j) {
  JobResult r;
  r.input = j.at("input");
  r.format = j.at("format");
  r.init_mode = j.at("init_mode");
  r.init_ns = j.at("init_ns");
  r.keep_from_ns = j.at("keep_from_ns");
  r.keep_to_ns = j.at("keep_to_ns");
  for (const auto& f : j.at("frames")) {
    FrameRecord fr{f.at("t"), poseFrom(f.at("p")), {}, MclStatus(f.at("s").get<int>()), f.at("e"), f.at("n"), f.at("v"), f.at("r"), f.value("f", -1.0)};
    for (int i = 0; i < 36; ++i) fr.covariance.data()[i] = f.at("c")[i];
    r.frames.push_back(fr);
  }
  for (const auto& t : j.at("truth")) r.truth.push_back({t[0].get<int64_t>(), poseFrom(t[1])});
  r.truth_from_stream = j.at("truth_from_stream");
  r.counters = j.at("counters").get<std::map<std::string, uint64_t>>();
  r.updates = j.at("updates");
  r.final_particles = j.at("final_particles");
  r.final_status = MclStatus(j.at("final_status").get<int>());
  r.final_pose = poseFrom(j.at("final_pose"));
  r.filter_s = j.at("filter_s");
  r.wall_s = j.at("wall_s");
  r.plot.estimate_path = pointsFrom(j.at("path"));
  for (const auto& c : j.at("clouds"))
    r.plot.clouds.push_back({c.at("t"), c.at("u"), poseFrom(c.at("p")), pointsFrom(c.at("x"))});
  r.warnings = j.at("warnings").get<std::vector<std::string>>();
  return r;
}

}  // namespace

std::string encodeOutcomes(const std::vector<TaskOutcome>& outcomes) {
  json a = json::array();
  for (const auto& o : outcomes)
    a.push_back({{"task", o.task}, {"rank", o.rank}, {"ok", o.ok}, {"error", o.error}, {"log", o.log},
                 {"result", o.ok ? resultJson(o.result) : json(nullptr)}});
  const std::vector<uint8_t> bytes = json::to_cbor(a);
  return std::string(bytes.begin(), bytes.end());
}

std::vector<TaskOutcome> decodeOutcomes(const std::string& bytes) {
  std::vector<TaskOutcome> out;
  try {
    for (const auto& o : json::from_cbor(bytes)) {
      TaskOutcome t{o.at("task"), o.at("rank"), o.at("ok"), o.at("error"), o.at("log").get<std::vector<std::string>>(), {}};
      if (t.ok) t.result = resultFrom(o.at("result"));
      out.push_back(std::move(t));
    }
  } catch (const json::exception& e) {
    throw std::runtime_error(std::string("relocalize: outcomes from a rank cannot be decoded: ") + e.what());
  }
  return out;
}

}  // namespace polyloc::reloc
