/// Dashboard WebSocket: arbitrary text messages from a viewer, handled by
/// ViewerSession::on_message (watch a node, move a node). Each input is one
/// viewer's session; its messages are separated by '\n' (at most 8).
///
/// Checks, per message:
///  - the answer is nothing or exactly one {"type": "error", "message": "..."};
///  - a message that is answered without an error named an existing node by its
///    exact id (a "watch" of null is also fine);
///  - every node's position stays finite;
/// and after the viewer leaves, it watches nothing and holds no messages.
#include "dashboard_harness.hpp"

using rfsitl::fuzz::DashboardFixture;
using rfsitl::fuzz::fixture;
using Json = nlohmann::json;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  DashboardFixture& f = fixture();
  static boost::asio::io_context viewer_io;  // the viewer's socket; never connected
  // Odd-sized inputs come from a viewer without the control token (its moves
  // are refused), even-sized ones from a viewer that may move nodes.
  auto viewer = std::make_shared<rfsitl::monitor::ViewerSession>(
      boost::asio::ip::tcp::socket(viewer_io), *f.server,
      size % 2 == 1 ? std::string("no control token") : std::string());
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  std::size_t start = 0;
  for (int n = 0; n < 8 && start <= text.size(); ++n) {
    const std::size_t nl = text.find('\n', start);
    const std::size_t end = nl == std::string_view::npos ? text.size() : nl;
    const std::string message(text.substr(start, end - start));
    start = end + 1;
    if (viewer->finished_) break;  // a failed write (the socket is closed) ended it

    viewer->queue_.clear();
    viewer->on_message(message);
    FUZZ_CHECK(viewer->queue_.size() <= 1, "%zu answers to one message", viewer->queue_.size());
    if (viewer->queue_.size() == 1) {
      const Json a = Json::parse(*viewer->queue_.front().text, nullptr, false);
      FUZZ_CHECK(a.is_object() && a.value("type", "") == "error" && a.contains("message") &&
                     a["message"].is_string(),
                 "answer is not an error message: %s", viewer->queue_.front().text->c_str());
    } else {
      // Accepted: it named a node by its exact id (or watched nothing).
      const Json m = Json::parse(message, nullptr, false);
      FUZZ_CHECK(m.is_object() && m.contains("node"), "accepted without a node");
      const Json& node = m["node"];
      if (!(m["type"] == "watch" && node.is_null())) {
        bool named = false;
        for (const auto id : f.engine->node_ids()) {
          named = named || (node.is_number_unsigned() && node.get<std::uint64_t>() == id);
        }
        FUZZ_CHECK(named, "accepted a message for node %s", node.dump().c_str());
      }
    }
    f.check_positions();
    // The answer's write fails at once (the socket is not connected); run it
    // like the session's I/O thread would.
    viewer_io.restart();
    viewer_io.poll();
  }
  viewer->finish();  // the viewer leaves
  viewer_io.restart();
  viewer_io.poll();
  FUZZ_CHECK(!viewer->watching_ && viewer->queue_.empty(), "viewer state left after it left");
  return 0;
}
