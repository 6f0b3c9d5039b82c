// A recording held in memory: messages in the order given, read by as many readers as wanted
// (they share the messages). For runs a program makes itself (eval carmen's test runs, tests),
// so that they go through the same consumers as a file would.
#pragma once

#include <polyloc/io/recording.hpp>

#include <memory>
#include <string>
#include <vector>

namespace polyloc {

// A reader over `messages` (in their order; topics() counts them by topic and type).
std::unique_ptr<RecordingReader> readMemory(std::shared_ptr<const std::vector<RecordedMessage>> messages,
                                            std::string format = "memory");

}  // namespace polyloc
