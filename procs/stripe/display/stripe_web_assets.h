#pragma once
// The light-stripe page's files (web/ here), embedded at build time
// (common/display/display_page.cmake).

#include <string_view>

#include "common/display/web_assets.h"

namespace ephor::stripe_display {

// The asset served at `path`, or nullptr.
const display::WebAsset* find_web_asset(std::string_view path);

}  // namespace ephor::stripe_display
