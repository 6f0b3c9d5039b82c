#include <polyloc/io/restamp.hpp>

#include <cmath>
#include <stdexcept>
#include <string>

namespace polyloc {
namespace {

class RestampedReader final : public RecordingReader {
 public:
  RestampedReader(std::unique_ptr<RecordingReader> inner, double hz) : inner_(std::move(inner)), hz_(hz) {}

  std::vector<TopicInfo> topics() override {
    // Counts are the inner reader's; times follow from each topic's first and last message,
    // which only a pass can tell: restamp them by the order of the whole recording.
    std::vector<TopicInfo> t = inner_->topics();
    uint64_t total = 0;
    for (const auto& x : t) total += x.count;
    for (auto& x : t) x.first_ns = kRestampStartNs, x.last_ns = stampOf(total > 0 ? total - 1 : 0);
    return t;
  }
  bool next(RecordedMessage& out) override {
    if (!inner_->next(out)) return false;
    const int64_t t = stampOf(index_++);
    out.log_time_ns = out.publish_time_ns = t;
    setStamps(out.message, t);
    return true;
  }
  const ReadStats& stats() const override { return inner_->stats(); }
  std::string format() const override { return inner_->format(); }

 private:
  int64_t stampOf(uint64_t i) const { return restampedNs(i, hz_); }
  std::unique_ptr<RecordingReader> inner_;
  double hz_;
  uint64_t index_ = 0;
};

}  // namespace

void setStamps(msg::Message& m, int64_t t) {
  std::visit(
      [t](auto& x) {
        if constexpr (requires { x.header.stamp; }) x.header.stamp = msg::fromNs(t);
        if constexpr (requires { x.transforms; })
          for (auto& tf : x.transforms) tf.header.stamp = msg::fromNs(t);
      },
      m);
}

std::unique_ptr<RecordingReader> restampByOrder(std::unique_ptr<RecordingReader> reader, double hz) {
  if (!(std::isfinite(hz) && hz > 0 && hz <= 1e9))
    throw std::invalid_argument("restamp rate " + std::to_string(hz) + " Hz: must be a positive number up to 1e9");
  return std::make_unique<RestampedReader>(std::move(reader), hz);
}

}  // namespace polyloc
