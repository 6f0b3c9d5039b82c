// Where `polyloc play` takes its messages from, in log-time order: a recording, or a scenario
// simulated live in a thread of its own that runs ahead of playback by a bounded amount.
#pragma once

#include <polyloc/io/recording.hpp>
#include <polyloc/map/mesh.hpp>

#include <memory>
#include <string>

namespace polyloc::cli {

class PlaySource {
 public:
  virtual ~PlaySource() = default;
  virtual bool next(RecordedMessage& out) = 0;  // false at the end
  virtual double durationS() const = 0;         // of the whole source, for progress
  virtual std::string describe() const = 0;
  virtual const Mesh* map() const { return nullptr; }  // a live simulation's map (for the plot)
};

std::unique_ptr<PlaySource> playRecording(const std::string& path);
// duration_s > 0 cuts the scenario short (a longer one is not lengthened).
std::unique_ptr<PlaySource> playScenario(const std::string& path, double duration_s);

}  // namespace polyloc::cli
