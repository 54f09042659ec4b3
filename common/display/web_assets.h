#pragma once
// A display page's files, embedded at build time by embed_assets.cmake (see
// display_page.cmake) so a display binary needs no files at run time. Each
// page's generated source defines find_web_asset() in the page's namespace;
// this header declares the shepherding page's (web/ here).

#include <cstddef>
#include <string_view>

namespace ephor::display {

struct WebAsset {
  const char* path;          // URL path, e.g. "/index.html"
  const char* content_type;  // HTTP Content-Type
  const unsigned char* data;
  size_t size;  // bytes (data has one extra 0 byte after them)
};

// The shepherding page's asset served at `path`, or nullptr.
const WebAsset* find_web_asset(std::string_view path);

}  // namespace ephor::display
