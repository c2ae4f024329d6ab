#pragma once
/// The dashboard's files (web/dashboard/), compiled into the binary by
/// cmake/embed_assets.cmake so the page needs nothing from outside.
#include <span>
#include <string_view>

namespace rfsitl::monitor {

struct WebAsset {
  std::string_view path;  ///< "/index.html", "/main.js", ...
  std::string_view content_type;
  std::string_view body;
};

std::span<const WebAsset> web_assets();

}  // namespace rfsitl::monitor
