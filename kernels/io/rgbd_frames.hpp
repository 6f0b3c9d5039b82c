// The reader both depth data set layouts share (io/rgbd_dataset.hpp): a list of frames (stamp,
// depth PNG, optical-frame pose where there is one) streamed as camera info, image and ground
// truth. Images are decoded one at a time as next() reaches them: memory stays one frame. A frame
// that cannot be decoded, or differs in size or pixel type from the first, is counted, warned
// (file, frame) and skipped; its ground truth is still delivered. Private to kernels/io.
#pragma once

#include <polyloc/io/rgbd_dataset.hpp>

#include <deque>
#include <optional>
#include <string>
#include <vector>

namespace polyloc::io_detail {

struct RgbdFrame {
  int64_t stamp_ns = 0;
  std::string depth_path;
  std::optional<Pose> world_T_optical;
};

class RgbdFrameReader final : public RecordingReader {
 public:
  // Throws IoError when no frame's image can be read to learn the size from. `notes`: what the
  // layout's reader decided on its own (defaults, stamps made up, frames without truth).
  RgbdFrameReader(std::string name, std::string format, std::vector<RgbdFrame> frames, const RgbdIntrinsics& k,
                  ReadStats stats);
  std::vector<TopicInfo> topics() override;
  bool next(RecordedMessage& out) override;
  const ReadStats& stats() const override { return stats_; }
  std::string format() const override { return format_; }

 private:
  // 16-bit depth PNG -> 32FC1 metres; nullopt (and a warning) when it is not one of the size.
  std::optional<msg::Image> decode(const RgbdFrame& f, size_t index);

  std::string name_, format_;
  std::vector<RgbdFrame> frames_;
  RgbdIntrinsics k_;
  ReadStats stats_;
  int width_ = 0, height_ = 0;
  size_t next_frame_ = 0;
  std::deque<RecordedMessage> pending_;
};

// The folder's intrinsics: `file` if given, else DIR/intrinsics.yaml where there is one, else
// `layout` (the layout's own file or defaults). Notes which one.
RgbdIntrinsics chooseIntrinsics(const std::string& dir, const std::string& file, RgbdIntrinsics layout, ReadStats& stats);

}  // namespace polyloc::io_detail
