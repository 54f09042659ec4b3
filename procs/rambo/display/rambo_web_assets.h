#pragma once
// The RAMBO page's files (web/ here and the shared ephor_page.js/.css),
// embedded at build time (common/display/display_page.cmake).

#include <string_view>

#include "common/display/web_assets.h"

namespace ephor::rambo_display {

// The asset served at `path`, or nullptr.
const display::WebAsset* find_web_asset(std::string_view path);

}  // namespace ephor::rambo_display
