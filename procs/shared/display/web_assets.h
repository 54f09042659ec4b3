#pragma once
// The page's files (procs/shared/display/web/), embedded at build time by
// embed_assets.cmake so the binary needs no files at run time.

#include <cstddef>
#include <string_view>

namespace ephor::display {

struct WebAsset {
  const char* path;          // URL path, e.g. "/index.html"
  const char* content_type;  // HTTP Content-Type
  const unsigned char* data;
  size_t size;  // bytes (data has one extra 0 byte after them)
};

// The asset served at `path`, or nullptr.
const WebAsset* find_web_asset(std::string_view path);

}  // namespace ephor::display
