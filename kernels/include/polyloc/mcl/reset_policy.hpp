// When the filter searches globally (the coarse rounds after a uniform prior) and when it gives a
// track up and starts over from a uniform prior (sensor resetting). Decisions only: the Localizer
// draws the particles.
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/mcl/config.hpp>

#include <cstddef>

namespace polyloc {

class ResetPolicy {
 public:
  ResetPolicy() = default;
  explicit ResetPolicy(const MclConfig& config);

  void reset();        // the filter was re-initialised: no coarse rounds, nothing counted
  void startGlobal();  // a uniform prior was drawn: its coarse rounds begin
  bool coarse() const { return coarse_left_ > 0; }  // the next frames are weighed coarse
  size_t globalRounds() const { return global_rounds_; }  // coarse rounds since the last uniform prior

  // A round closes. True: one of the rounds right after a uniform prior (global localisation).
  bool beginRound();
  // The estimate `now` lies farther than relocalize_jump from where odometry `predicted` the
  // last one (which was tracking): taken over by injected particles.
  bool jumped(bool was_tracking, bool global_round, const Pose& now, const Pose& predicted) const;
  // One more coarse round unless the global round's estimate is confirmed.
  void extendGlobal(bool global_round, bool contradicted, bool refined, bool ambiguous);
  // Counts the round; true when the filter should start over from a uniform prior.
  bool relocalize(bool jumped, bool contradicted, bool refined);

 private:
  size_t global_coarse_rounds_ = 0, global_max_coarse_rounds_ = 0, relocalize_rounds_ = 0;
  double relocalize_jump_ = 0;
  size_t low_rounds_ = 0, rounds_since_reset_ = 0;  // sensor resetting (relocalize_rounds)
  size_t coarse_left_ = 0;    // rounds still weighed coarse after a uniform prior
  size_t global_rounds_ = 0;  // coarse rounds since the last uniform prior
};

}  // namespace polyloc
