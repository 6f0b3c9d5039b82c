// Checked YAML configuration: read keys with defaults, and turn every mistake into an error that
// names the file, the line and the key ("lab.yaml:12:3: robot.height: expected a number, got
// 'tall'"). A ConfigMap remembers which keys were read, so finish() can reject the keys nobody
// asked for (typos would otherwise be silently ignored).
//
// Conventions of polyloc's YAML: lengths in metres, times in seconds, rates in Hz; angles in
// degrees, or as a string with a unit ("1.5708 rad", "90 deg"); file paths relative to the file
// that names them.
#pragma once

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace polyloc {

class ConfigMap;

class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// One value in a file, with where it came from. Conversions throw ConfigError.
class ConfigValue {
 public:
  ConfigValue(YAML::Node node, std::shared_ptr<const std::string> file, std::string key);

  const YAML::Node& node() const { return node_; }
  const std::string& file() const { return *file_; }
  const std::string& key() const { return key_; }  // dotted path, "route.waypoints[2]"
  std::string where() const;                       // "file:line:column"
  [[noreturn]] void fail(const std::string& what) const;

  bool isMap() const { return node_.IsMap(); }
  bool isSequence() const { return node_.IsSequence(); }
  bool isScalar() const { return node_.IsScalar(); }

  double asDouble() const;  // finite
  int64_t asInt() const;
  bool asBool() const;
  std::string asString() const;
  double asAngle() const;   // number = degrees; "x deg" / "x rad"; returns radians
  // Sequence of numbers, optionally of a fixed size (0 = any).
  std::vector<double> asDoubles(size_t size = 0) const;
  std::vector<ConfigValue> items() const;  // elements of a sequence
  ConfigMap asMap() const;

 private:
  YAML::Node node_;
  std::shared_ptr<const std::string> file_;
  std::string key_;
};

class ConfigMap {
 public:
  ConfigMap(YAML::Node node, std::shared_ptr<const std::string> file, std::string prefix);
  // Top level of a file; an empty file is an empty map. Throws ConfigError on syntax errors.
  static ConfigMap load(const std::string& file);
  static ConfigMap parse(const std::string& text, const std::string& name = "<string>");

  const std::string& file() const { return *file_; }
  const std::string& prefix() const { return prefix_; }
  std::string keyPath(const std::string& key) const;  // "prefix.key"
  std::string where() const;                          // position of the mapping itself
  [[noreturn]] void fail(const std::string& what) const;  // error about the mapping itself

  bool has(const std::string& key) const;
  // The value of a key, marked as read; throws ConfigError if it is missing.
  ConfigValue value(const std::string& key);
  // Marks a key as known without reading it (a section parsed elsewhere).
  void allow(const std::string& key) { known_->insert(key); }

  double getDouble(const std::string& key, double def);
  double getAngle(const std::string& key, double def_rad);
  int64_t getInt(const std::string& key, int64_t def);
  // An integer in [lo, hi], for counts; the error names the range.
  size_t getCount(const std::string& key, size_t def, size_t lo, size_t hi);
  bool getBool(const std::string& key, bool def);
  std::string getString(const std::string& key, const std::string& def);
  // One of `choices`; the error lists them.
  std::string getChoice(const std::string& key, const std::string& def,
                        const std::vector<std::string>& choices);
  // A path relative to the directory of this file, made absolute-or-relative-to-cwd.
  std::string getPath(const std::string& key, const std::string& def);
  std::string resolvePath(const std::string& path) const;
  // Range checks: fail naming the key when v is outside [lo, hi].
  double getDouble(const std::string& key, double def, double lo, double hi);

  ConfigMap map(const std::string& key);  // nested mapping (must be one)

  // Throws ConfigError naming the first key that was never read, and the keys that were.
  void finish() const;

 private:
  YAML::Node node_;
  std::shared_ptr<const std::string> file_;
  std::string prefix_;
  std::shared_ptr<std::set<std::string>> known_;  // shared by copies: reading through a copy counts
};

// "file:line:column" of a node (1-based), or just the file when the node has no position.
std::string configWhere(const std::string& file, const YAML::Node& node);

}  // namespace polyloc
