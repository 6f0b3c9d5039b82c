// The picture of `polyloc eval rgbd`: one frame's measured depth, the mesh rendered at its ground
// truth and the pixel labels with the filter's removals, above the agreement floor over the frames.
#pragma once

#include <polyloc/eval/rgbd_eval.hpp>

#include <string>

namespace polyloc::viz {

// Throws std::runtime_error naming the file when it cannot be written.
void drawRgbdEval(const RgbdEvalResult& result, const std::string& title, const std::string& png);

}  // namespace polyloc::viz
