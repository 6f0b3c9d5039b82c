#include "reloc/progress_board.hpp"

#include <fmt/core.h>

#include <cstdio>

namespace polyloc::reloc {

ProgressBoard::ProgressBoard(std::vector<std::string> labels, bool enabled)
    : labels_(std::move(labels)), fraction_(new std::atomic<float>[labels_.size()]), enabled_(enabled) {
  for (size_t i = 0; i < labels_.size(); ++i) fraction_[i] = -1.f;
}

void ProgressBoard::start(size_t task) { fraction_[task] = 0.f, draw(true); }
void ProgressBoard::update(size_t task, double fraction) { fraction_[task] = float(fraction), draw(false); }
void ProgressBoard::finish(size_t task) { fraction_[task] = 2.f, draw(true); }

void ProgressBoard::message(const std::string& line) {
  std::lock_guard lock(draw_);
  fmt::print(stderr, "{}{}\n", enabled_ ? "\r\033[K" : "", line);
  std::fflush(stderr);
}

void ProgressBoard::draw(bool force) {
  if (!enabled_) return;
  std::unique_lock lock(draw_, std::try_to_lock);
  if (!lock) return;  // someone draws already
  const auto now = std::chrono::steady_clock::now();
  if (!force && now - last_ < std::chrono::milliseconds(100)) return;
  last_ = now;
  double sum = 0;
  size_t done = 0;
  std::string running;
  for (size_t i = 0; i < labels_.size(); ++i) {
    const float f = fraction_[i];
    if (f > 1.5f) ++done, sum += 1;
    else if (f >= 0) sum += f, running += fmt::format(" | {} {:3.0f}%", labels_[i], 100 * f);
  }
  const double overall = labels_.empty() ? 1.0 : sum / double(labels_.size());
  const int width = 30, bar = int(overall * width);
  fmt::print(stderr, "\r\033[Krelocalize [{}{}] {:3.0f}% {}/{} done{}", std::string(bar, '='),
             std::string(width - bar, ' '), 100 * overall, done, labels_.size(), running);
  std::fflush(stderr);
}

void ProgressBoard::close() {
  if (!enabled_) return;
  draw(true);
  std::lock_guard lock(draw_);
  fmt::print(stderr, "\n");
}

}  // namespace polyloc::reloc
