#include <polyloc/config/yaml.hpp>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace polyloc {

namespace {

std::string shown(const YAML::Node& n) {
  if (!n.IsDefined() || n.IsNull()) return "nothing";
  if (n.IsScalar()) return "'" + n.Scalar() + "'";
  if (n.IsSequence()) return "a list";
  return "a mapping";
}

// strtod over the whole scalar; YAML's own spellings of infinity and NaN are not numbers here.
bool parseDouble(const std::string& s, double& out) {
  if (s.empty()) return false;
  char* end = nullptr;
  errno = 0;
  out = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && errno == 0 && std::isfinite(out);
}

std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t");
  if (a == std::string::npos) return "";
  const size_t b = s.find_last_not_of(" \t");
  return s.substr(a, b - a + 1);
}

}  // namespace

std::string configWhere(const std::string& file, const YAML::Node& node) {
  if (!node.IsDefined()) return file;
  const YAML::Mark m = node.Mark();
  if (m.is_null()) return file;
  return file + ":" + std::to_string(m.line + 1) + ":" + std::to_string(m.column + 1);
}

// ---------------------------------------------------------------------------------- ConfigValue

ConfigValue::ConfigValue(YAML::Node node, std::shared_ptr<const std::string> file, std::string key)
    : node_(std::move(node)), file_(std::move(file)), key_(std::move(key)) {}

std::string ConfigValue::where() const { return configWhere(*file_, node_); }

void ConfigValue::fail(const std::string& what) const {
  throw ConfigError(where() + ": " + key_ + ": " + what);
}

double ConfigValue::asDouble() const {
  double v;
  if (!node_.IsScalar() || !parseDouble(node_.Scalar(), v))
    fail("expected a number, got " + shown(node_));
  return v;
}

int64_t ConfigValue::asInt() const {
  if (node_.IsScalar()) {
    const std::string& s = node_.Scalar();
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(s.c_str(), &end, 10);
    if (!s.empty() && end == s.c_str() + s.size() && errno == 0) return v;
    // "1e7" is an integer too, when it is one exactly and fits (checked before any narrowing).
    double d;
    if (parseDouble(s, d) && d == std::floor(d) && std::abs(d) < 9.2e18) return int64_t(d);
  }
  fail("expected an integer, got " + shown(node_));
}

bool ConfigValue::asBool() const {
  if (node_.IsScalar()) {
    const std::string& s = node_.Scalar();
    if (s == "true" || s == "True" || s == "yes" || s == "on") return true;
    if (s == "false" || s == "False" || s == "no" || s == "off") return false;
  }
  fail("expected true or false, got " + shown(node_));
}

std::string ConfigValue::asString() const {
  if (!node_.IsScalar()) fail("expected a text value, got " + shown(node_));
  return node_.Scalar();
}

double ConfigValue::asAngle() const {
  if (!node_.IsScalar()) fail("expected an angle (degrees, or \"x rad\"), got " + shown(node_));
  const std::string s = trim(node_.Scalar());
  double v;
  if (parseDouble(s, v)) return v * M_PI / 180.0;
  for (const auto& [unit, factor] : {std::pair<const char*, double>{"deg", M_PI / 180.0},
                                     std::pair<const char*, double>{"rad", 1.0}}) {
    const std::string u(unit);
    if (s.size() > u.size() && s.compare(s.size() - u.size(), u.size(), u) == 0 &&
        parseDouble(trim(s.substr(0, s.size() - u.size())), v))
      return v * factor;
  }
  fail("expected an angle in degrees (a number), or a number with unit \"deg\" or \"rad\", got " +
       shown(node_));
}

std::vector<double> ConfigValue::asDoubles(size_t size) const {
  if (!node_.IsSequence() || (size && node_.size() != size))
    fail(size ? "expected a list of " + std::to_string(size) + " numbers, got " + shown(node_) +
                    (node_.IsSequence() ? " of " + std::to_string(node_.size()) : "")
              : "expected a list of numbers, got " + shown(node_));
  std::vector<double> out;
  for (const ConfigValue& v : items()) out.push_back(v.asDouble());
  return out;
}

std::vector<ConfigValue> ConfigValue::items() const {
  if (!node_.IsSequence()) fail("expected a list, got " + shown(node_));
  std::vector<ConfigValue> out;
  for (size_t i = 0; i < node_.size(); ++i)
    out.emplace_back(node_[i], file_, key_ + "[" + std::to_string(i) + "]");
  return out;
}

ConfigMap ConfigValue::asMap() const {
  if (!node_.IsMap()) fail("expected a mapping (key: value lines), got " + shown(node_));
  return ConfigMap(node_, file_, key_);
}

// ------------------------------------------------------------------------------------ ConfigMap

ConfigMap::ConfigMap(YAML::Node node, std::shared_ptr<const std::string> file, std::string prefix)
    : node_(std::move(node)),
      file_(std::move(file)),
      prefix_(std::move(prefix)),
      known_(std::make_shared<std::set<std::string>>()) {
  // yaml-cpp keeps a repeated key and lookups return its first value: the later one would be
  // silently dropped, so a repeated key is an error naming both places.
  if (!node_.IsMap()) return;
  std::map<std::string, YAML::Node> seen;
  for (const auto& kv : node_) {
    if (!kv.first.IsScalar()) continue;
    const auto [it, fresh] = seen.emplace(kv.first.Scalar(), kv.first);
    if (!fresh)
      throw ConfigError(configWhere(*file_, kv.first) + ": " + keyPath(kv.first.Scalar()) +
                        ": repeated key (first at " + configWhere(*file_, it->second) + ")");
  }
}

ConfigMap ConfigMap::load(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw ConfigError(file + ": cannot open the file");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse(ss.str(), file);
}

ConfigMap ConfigMap::parse(const std::string& text, const std::string& name) {
  auto file = std::make_shared<const std::string>(name);
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw ConfigError(name + ":" + std::to_string(e.mark.line + 1) + ":" +
                      std::to_string(e.mark.column + 1) + ": YAML syntax error: " + e.msg);
  }
  if (!root.IsDefined() || root.IsNull()) root = YAML::Node(YAML::NodeType::Map);
  if (!root.IsMap()) throw ConfigError(configWhere(name, root) + ": expected a mapping at the top level");
  return ConfigMap(root, file, "");
}

std::string ConfigMap::keyPath(const std::string& key) const {
  return prefix_.empty() ? key : prefix_ + "." + key;
}

std::string ConfigMap::where() const { return configWhere(*file_, node_); }

void ConfigMap::fail(const std::string& what) const {
  throw ConfigError(where() + ": " + (prefix_.empty() ? "" : prefix_ + ": ") + what);
}

bool ConfigMap::has(const std::string& key) const {
  known_->insert(key);
  const YAML::Node n = node_[key];
  return n.IsDefined() && !n.IsNull();
}

ConfigValue ConfigMap::value(const std::string& key) {
  known_->insert(key);
  const YAML::Node n = node_[key];
  if (!n.IsDefined() || n.IsNull()) fail("missing key '" + key + "'");
  return ConfigValue(n, file_, keyPath(key));
}

double ConfigMap::getDouble(const std::string& key, double def) {
  return has(key) ? value(key).asDouble() : def;
}

double ConfigMap::getDouble(const std::string& key, double def, double lo, double hi) {
  if (!has(key)) return def;
  const ConfigValue v = value(key);
  const double d = v.asDouble();
  if (d < lo || d > hi) {
    std::ostringstream os;
    os << "must be in [" << lo << ", " << hi << "], got " << d;
    v.fail(os.str());
  }
  return d;
}

double ConfigMap::getAngle(const std::string& key, double def_rad) {
  return has(key) ? value(key).asAngle() : def_rad;
}

int64_t ConfigMap::getInt(const std::string& key, int64_t def) {
  return has(key) ? value(key).asInt() : def;
}

size_t ConfigMap::getCount(const std::string& key, size_t def, size_t lo, size_t hi) {
  if (!has(key)) return def;
  const ConfigValue v = value(key);
  const int64_t n = v.asInt();
  if (n < 0 || size_t(n) < lo || size_t(n) > hi)
    v.fail("must be between " + std::to_string(lo) + " and " + std::to_string(hi) + ", got " + std::to_string(n));
  return size_t(n);
}

bool ConfigMap::getBool(const std::string& key, bool def) {
  return has(key) ? value(key).asBool() : def;
}

std::string ConfigMap::getString(const std::string& key, const std::string& def) {
  return has(key) ? value(key).asString() : def;
}

std::string ConfigMap::getChoice(const std::string& key, const std::string& def,
                                 const std::vector<std::string>& choices) {
  if (!has(key)) return def;
  const ConfigValue v = value(key);
  const std::string s = v.asString();
  std::string list;
  for (const std::string& c : choices) {
    if (c == s) return s;
    list += (list.empty() ? "" : ", ") + c;
  }
  v.fail("expected one of " + list + ", got '" + s + "'");
}

std::string ConfigMap::resolvePath(const std::string& path) const {
  namespace fs = std::filesystem;
  const fs::path p(path);
  if (p.is_absolute() || file_->empty() || file_->front() == '<') return path;
  return (fs::path(*file_).parent_path() / p).lexically_normal().string();
}

std::string ConfigMap::getPath(const std::string& key, const std::string& def) {
  return has(key) ? resolvePath(value(key).asString()) : (def.empty() ? def : resolvePath(def));
}

ConfigMap ConfigMap::map(const std::string& key) {
  if (!has(key)) {  // an absent section reads as empty: every key takes its default
    YAML::Node empty(YAML::NodeType::Map);
    return ConfigMap(empty, file_, keyPath(key));
  }
  return value(key).asMap();
}

void ConfigMap::finish() const {
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    const std::string k = it->first.Scalar();
    if (known_->count(k)) continue;
    std::string list;
    for (const std::string& s : *known_) list += (list.empty() ? "" : ", ") + s;
    throw ConfigError(configWhere(*file_, it->first) + ": unknown key '" + keyPath(k) + "'" +
                      (list.empty() ? "" : " (known here: " + list + ")"));
  }
}

}  // namespace polyloc
