#include <polyloc/io/memory_recording.hpp>

#include <algorithm>
#include <map>

namespace polyloc {
namespace {

class MemoryReader final : public RecordingReader {
 public:
  MemoryReader(std::shared_ptr<const std::vector<RecordedMessage>> m, std::string format)
      : messages_(std::move(m)), format_(std::move(format)) {}

  std::vector<TopicInfo> topics() override {
    TopicTally tally;
    for (const RecordedMessage& m : *messages_) tally.add(m);
    return tally.topics();
  }
  bool next(RecordedMessage& out) override {
    if (pos_ >= messages_->size()) return false;
    out = (*messages_)[pos_++];
    ++stats_.messages;
    return true;
  }
  const ReadStats& stats() const override { return stats_; }
  std::string format() const override { return format_; }

 private:
  std::shared_ptr<const std::vector<RecordedMessage>> messages_;
  std::string format_;
  size_t pos_ = 0;
  ReadStats stats_;
};

}  // namespace

std::unique_ptr<RecordingReader> readMemory(std::shared_ptr<const std::vector<RecordedMessage>> messages,
                                            std::string format) {
  return std::make_unique<MemoryReader>(std::move(messages), std::move(format));
}

}  // namespace polyloc
