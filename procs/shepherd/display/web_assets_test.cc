#include "common/display/web_assets.h"

#include <string>

#include <gtest/gtest.h>

namespace ephor::display {
namespace {

TEST(WebAssetsTest, PageAndScriptAreEmbedded) {
  const auto* page = find_web_asset("/index.html");
  ASSERT_NE(page, nullptr);
  const std::string html(reinterpret_cast<const char*>(page->data), page->size);
  EXPECT_NE(html.find("display.js"), std::string::npos);
  EXPECT_EQ(std::string(page->content_type).rfind("text/html", 0), 0u);
  const auto* js = find_web_asset("/display.js");
  ASSERT_NE(js, nullptr);
  EXPECT_GT(js->size, 1000u);
  EXPECT_EQ(js->data[js->size], 0);  // terminated, for convenience
  EXPECT_EQ(find_web_asset("/secret"), nullptr);
}

}  // namespace
}  // namespace ephor::display
