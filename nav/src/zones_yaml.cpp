// loadZones: reading a zone file. The format and its errors are documented in polynav/zones.hpp.
#include <polynav/zones.hpp>

#include "zones_detail.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace polynav {

using namespace zones_detail;

namespace {

double wrapAngle(double a) { return std::atan2(std::sin(a), std::cos(a)); }

class Loader {
 public:
  explicit Loader(std::string file) : file_(std::move(file)) {}

  std::string where(const YAML::Node& n) const {
    if (!n.IsDefined()) return file_;
    const YAML::Mark m = n.Mark();
    if (m.is_null()) return file_;
    return file_ + ":" + std::to_string(m.line + 1) + ":" + std::to_string(m.column + 1);
  }
  [[noreturn]] void fail(const YAML::Node& n, const std::string& key, const std::string& what) const {
    throw ZonesError(where(n) + ": " + (key.empty() ? "" : key + ": ") + what);
  }

  static std::string shown(const YAML::Node& n) {
    if (!n.IsDefined() || n.IsNull()) return "nothing";
    if (n.IsScalar()) return "'" + n.Scalar() + "'";
    if (n.IsSequence()) return "a list";
    return "a mapping";
  }

  // The mapping `n` (key path `key`) with only the keys in `known`, each once.
  void checkKeys(const YAML::Node& n, const std::string& key, const std::vector<std::string>& known) const {
    if (!n.IsMap()) fail(n, key, "expected a mapping ({key: value, ...}), got " + shown(n));
    std::set<std::string> seen;
    for (auto it = n.begin(); it != n.end(); ++it) {
      const YAML::Node k = it->first;
      if (!k.IsScalar()) fail(k, key, "expected a text key, got " + shown(k));
      const std::string& name = k.Scalar();
      if (std::find(known.begin(), known.end(), name) == known.end()) {
        std::string list;
        for (const std::string& s : known) list += (list.empty() ? "" : ", ") + s;
        fail(k, key, "unknown key '" + name + "' (expected one of: " + list + ")");
      }
      if (!seen.insert(name).second) fail(k, key, "key '" + name + "' given twice");
    }
  }
  YAML::Node required(const YAML::Node& map, const std::string& key, const std::string& name) const {
    const YAML::Node n = map[name];
    if (!n.IsDefined()) fail(map, key, "missing key '" + name + "'");
    if (n.IsNull()) fail(n, key + "." + name, "missing value");
    return n;
  }
  static bool given(const YAML::Node& map, const std::string& name) {
    const YAML::Node n = map[name];
    return n.IsDefined() && !n.IsNull();
  }

  double number(const YAML::Node& n, const std::string& key) const {
    double v = 0;
    if (!n.IsScalar() || !parse(n.Scalar(), v)) fail(n, key, "expected a finite number, got " + shown(n));
    return v;
  }
  std::string text(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar()) fail(n, key, "expected a text, got " + shown(n));
    return n.Scalar();
  }
  bool boolean(const YAML::Node& n, const std::string& key) const {
    if (n.IsScalar()) {
      const std::string& s = n.Scalar();
      if (s == "true" || s == "True" || s == "yes" || s == "on") return true;
      if (s == "false" || s == "False" || s == "no" || s == "off") return false;
    }
    fail(n, key, "expected true or false, got " + shown(n));
  }
  double angleDeg(const YAML::Node& n, const std::string& key) const {
    if (n.IsScalar()) {
      const std::string s = trim(n.Scalar());
      double v = 0;
      if (parse(s, v)) return v * M_PI / 180.0;
      for (const auto& [unit, factor] : {std::pair<std::string, double>{"deg", M_PI / 180.0}, {"rad", 1.0}})
        if (s.size() > unit.size() && s.compare(s.size() - unit.size(), unit.size(), unit) == 0 &&
            parse(trim(s.substr(0, s.size() - unit.size())), v))
          return v * factor;
    }
    fail(n, key, "expected an angle in degrees (a finite number) or with a unit (\"90 deg\", \"1.57 rad\"), got " + shown(n));
  }
  Vector2d point(const YAML::Node& n, const std::string& key) const {
    if (!n.IsSequence() || n.size() != 2)
      fail(n, key, "expected a point [x, y], got " + shown(n) + (n.IsSequence() ? " of " + std::to_string(n.size()) : ""));
    return {number(n[0], key + "[0]"), number(n[1], key + "[1]")};
  }
  Vector2d direction(const YAML::Node& n, const std::string& key) const {
    const Vector2d v = point(n, key);
    if (!(v.norm() > 1e-9)) fail(n, key, "must not be zero, got " + pt(v));
    return v.normalized();
  }
  Polygon polygon(const YAML::Node& n, const std::string& key) const {
    if (!n.IsSequence()) fail(n, key, "expected a list of points [[x, y], ...], got " + shown(n));
    Polygon out;
    for (size_t i = 0; i < n.size(); ++i) out.push_back(point(n[i], key + "[" + std::to_string(i) + "]"));
    if (const std::string p = polygonProblem(out); !p.empty()) fail(n, key, "the polygon " + p);
    return out;
  }

  // The list under top-level key `name` (empty when absent or null), each item with its key path.
  std::vector<std::pair<YAML::Node, std::string>> items(const YAML::Node& root, const std::string& name) const {
    std::vector<std::pair<YAML::Node, std::string>> out;
    const YAML::Node n = root[name];
    if (!n.IsDefined() || n.IsNull()) return out;
    if (!n.IsSequence()) fail(n, name, "expected a list, got " + shown(n));
    for (size_t i = 0; i < n.size(); ++i) out.emplace_back(n[i], name + "[" + std::to_string(i) + "]");
    return out;
  }

  // Unique, non-empty names within one section.
  class Names {
   public:
    explicit Names(const Loader& l) : l_(l) {}
    std::string take(const YAML::Node& item, const std::string& key) {
      const YAML::Node n = l_.required(item, key, "name");
      const std::string name = l_.text(n, key + ".name");
      if (name.empty()) l_.fail(n, key + ".name", "the name is empty");
      auto [it, fresh] = seen_.emplace(name, std::pair{key, n.Mark().line + 1});
      if (!fresh)
        l_.fail(n, key + ".name",
                "duplicate name '" + name + "' (also " + it->second.first + ", line " + std::to_string(it->second.second) + ")");
      return name;
    }

   private:
    const Loader& l_;
    std::map<std::string, std::pair<std::string, int>> seen_;
  };

 private:
  static std::string trim(const std::string& s) {
    const size_t a = s.find_first_not_of(" \t");
    if (a == std::string::npos) return "";
    return s.substr(a, s.find_last_not_of(" \t") - a + 1);
  }
  static bool parse(const std::string& s, double& out) {
    if (s.empty()) return false;
    char* end = nullptr;
    errno = 0;
    out = std::strtod(s.c_str(), &end);
    return end == s.c_str() + s.size() && errno == 0 && std::isfinite(out);
  }

  std::string file_;
};

}  // namespace

Zones loadZones(const std::string& yaml_path) {
  const Loader l(yaml_path);
  std::ifstream in(yaml_path, std::ios::binary);
  if (!in) throw ZonesError(yaml_path + ": cannot open the file");
  std::stringstream ss;
  ss << in.rdbuf();
  YAML::Node root;
  try {
    root = YAML::Load(ss.str());
  } catch (const YAML::Exception& e) {
    throw ZonesError(yaml_path + ":" + std::to_string(e.mark.line + 1) + ":" + std::to_string(e.mark.column + 1) +
                     ": YAML syntax error: " + e.msg);
  }
  Zones z;
  if (!root.IsDefined() || root.IsNull()) return z;
  l.checkKeys(root, "", {"rooms", "doors", "corridors", "danger", "goals"});

  {
    Loader::Names names(l);
    for (const auto& [n, key] : l.items(root, "rooms")) {
      l.checkKeys(n, key, {"name", "polygon"});
      Room r;
      r.name = names.take(n, key);
      r.polygon = l.polygon(l.required(n, key, "polygon"), key + ".polygon");
      z.rooms.push_back(std::move(r));
    }
  }
  {
    Loader::Names names(l);
    for (const auto& [n, key] : l.items(root, "doors")) {
      l.checkKeys(n, key, {"name", "centre", "along", "width", "depth", "wall", "closed"});
      Door d;
      d.name = names.take(n, key);
      d.centre = l.point(l.required(n, key, "centre"), key + ".centre");
      d.along = l.direction(l.required(n, key, "along"), key + ".along");
      const YAML::Node w = l.required(n, key, "width");
      d.width = l.number(w, key + ".width");
      if (!(d.width > 0)) l.fail(w, key + ".width", "must be > 0, got " + num(d.width));
      if (Loader::given(n, "depth")) {
        d.depth = l.number(n["depth"], key + ".depth");
        if (!(d.depth > 0)) l.fail(n["depth"], key + ".depth", "must be > 0, got " + num(d.depth));
      }
      if (Loader::given(n, "wall")) {
        d.wall = l.number(n["wall"], key + ".wall");
        if (!(d.wall >= 0)) l.fail(n["wall"], key + ".wall", "must be >= 0, got " + num(d.wall));
      }
      if (Loader::given(n, "closed")) d.closed = l.boolean(n["closed"], key + ".closed");
      z.doors.push_back(std::move(d));
    }
  }
  {
    Loader::Names names(l);
    for (const auto& [n, key] : l.items(root, "corridors")) {
      l.checkKeys(n, key, {"name", "polygon", "axis"});
      Corridor c;
      c.name = names.take(n, key);
      c.polygon = l.polygon(l.required(n, key, "polygon"), key + ".polygon");
      c.axis = l.direction(l.required(n, key, "axis"), key + ".axis");
      z.corridors.push_back(std::move(c));
    }
  }
  {
    Loader::Names names(l);
    for (const auto& [n, key] : l.items(root, "danger")) {
      l.checkKeys(n, key, {"name", "polygon"});
      DangerZone d;
      d.name = names.take(n, key);
      d.polygon = l.polygon(l.required(n, key, "polygon"), key + ".polygon");
      z.danger.push_back(std::move(d));
    }
  }
  {
    Loader::Names names(l);
    for (const auto& [n, key] : l.items(root, "goals")) {
      l.checkKeys(n, key, {"name", "pose", "approach"});
      GoalSpot g;
      g.name = names.take(n, key);
      const YAML::Node p = l.required(n, key, "pose");
      if (!p.IsSequence() || p.size() != 3)
        l.fail(p, key + ".pose",
               "expected [x, y, yaw in degrees], got " + Loader::shown(p) +
                   (p.IsSequence() ? " of " + std::to_string(p.size()) : ""));
      g.pose = {l.number(p[0], key + ".pose[0]"), l.number(p[1], key + ".pose[1]"),
                wrapAngle(l.angleDeg(p[2], key + ".pose[2]"))};
      if (Loader::given(n, "approach")) {
        g.approach = l.number(n["approach"], key + ".approach");
        if (!(g.approach >= 0 && g.approach <= kMaxApproach))
          l.fail(n["approach"], key + ".approach", "must be in [0, 10] m, got " + num(g.approach));
      }
      // Rooms, corridors and danger are read before the goals, wherever they stand in the file.
      if (const std::string d = goalProblem(z, g); !d.empty()) l.fail(p, key + ".pose", d);
      z.goals.push_back(std::move(g));
    }
  }
  try {
    z.validate();
  } catch (const std::invalid_argument& e) {
    throw ZonesError(yaml_path + ": " + e.what());
  }
  return z;
}

}  // namespace polynav
