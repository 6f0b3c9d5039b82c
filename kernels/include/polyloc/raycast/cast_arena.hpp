// The worker pool of a ray-casting backend: a TBB arena of the configured size and the one
// parallel loop shape the batch calls use (chunks of [begin, end) over rays or poses).
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <memory>

namespace polyloc {

class CastArena {
 public:
  explicit CastArena(int threads = 0) { resize(threads); }
  // 0 = all cores; < 0 = no arena of its own: the loops run in the caller's (batch
  // relocalisation runs many recordings, each with its caster, in one arena).
  void resize(int threads) {
    if (threads < 0) {
      threads_ = -1;
      arena_.reset();
      return;
    }
    threads_ = threads > 0 ? threads : tbb::this_task_arena::max_concurrency();
    arena_ = std::make_unique<tbb::task_arena>(threads_);
  }
  int threads() const { return threads_ > 0 ? threads_ : tbb::this_task_arena::max_concurrency(); }
  // body(begin, end) over [0, n) in chunks of at least `grain`.
  template <class F>
  void parallel(size_t n, size_t grain, F&& body) const {
    auto loop = [&] {
      tbb::parallel_for(tbb::blocked_range<size_t>(0, n, grain),
                        [&](const tbb::blocked_range<size_t>& r) { body(r.begin(), r.end()); });
    };
    if (arena_) arena_->execute(loop);
    else loop();
  }

 private:
  std::unique_ptr<tbb::task_arena> arena_;
  int threads_ = 0;
};

}  // namespace polyloc
