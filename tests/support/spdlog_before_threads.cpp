/// Creates spdlog's default logger while the test program is still
/// single-threaded (before main). It is a function-local static inside the
/// library, whose guard ThreadSanitizer cannot see: a test thread meeting it
/// after another thread created it would look unordered after that creation
/// (scripts/test_tsan.sh). apps/rfsitl/main.cpp does the same for the emulator.
#include <spdlog/spdlog.h>

namespace {

const bool kDefaultLoggerCreated = (spdlog::default_logger_raw(), true);

}  // namespace
