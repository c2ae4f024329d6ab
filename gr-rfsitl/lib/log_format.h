#pragma once
/// Logging helpers for the rfsitl blocks.
#include <gnuradio/logger.h>

#include <fmt/format.h>
#include <utility>

namespace gr::rfsitl {

// gr::logger passes its format string on as a runtime string_view, which fmt 9
// rejects under C++20 (format strings must be constant expressions there), so
// the message is formatted here, with the compile-time check, and logged as
// one string.

template <typename... Args>
void log_info(gr::logger& l, fmt::format_string<Args...> f, Args&&... args) {
  l.info(fmt::format(f, std::forward<Args>(args)...));
}

template <typename... Args>
void log_warn(gr::logger& l, fmt::format_string<Args...> f, Args&&... args) {
  l.warn(fmt::format(f, std::forward<Args>(args)...));
}

template <typename... Args>
void log_error(gr::logger& l, fmt::format_string<Args...> f, Args&&... args) {
  l.error(fmt::format(f, std::forward<Args>(args)...));
}

}  // namespace gr::rfsitl
