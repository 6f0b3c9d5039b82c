// The live view's page (service/live/page.html), built into the binary: one self-contained
// HTML file, no outside scripts, so that it works on a robot without internet.
#pragma once

#include <string>

namespace polyloc::live {

const std::string& livePage();

}  // namespace polyloc::live
