/// `rfsitl links`: the live link table of a running emulator, read from its
/// dashboard's GET /api/links (the data the dashboard's link matrix shows):
/// per ordered pair tx -> rx the distance, path gain, SNR, the receiver's
/// declared PER estimate and the frames decoded and lost. Exit status: 0 when
/// it printed the table, 1 when the emulator could not be reached or did not
/// answer with a link table, 2 for bad options.
#include <utility>  // GCC 12 + C++20: before Boost.Asio

// GCC 12 at -O2 sees Beast's response parser (which only clients use) read a
// boost::optional it may not have set: a known false positive.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#pragma GCC diagnostic pop
#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "commands.hpp"
#include "rfsitl/monitor/link_table.hpp"

namespace rfsitl::app {
namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;

/// The whole table of 254 nodes is about 6 MB; more is not a link table.
constexpr std::size_t kMaxReplyBytes = 64 * 1024 * 1024;

struct LinksOptions {
  std::string host = "127.0.0.1";
  std::uint16_t dashboard_port = 15700;
  std::size_t top = 0;
  std::size_t worst = 0;
  std::optional<double> min_snr_db;
  std::size_t size = 80;
  double timeout_s = 5.0;
  bool json = false;
};

/// GET `target` from the dashboard; the body of a 200 reply. Throws naming
/// what failed (with the server's own error text for other statuses).
std::string http_get(const LinksOptions& o, const std::string& target) {
  asio::io_context io;
  beast::tcp_stream stream(io);
  stream.expires_after(std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(o.timeout_s)));
  asio::ip::tcp::resolver resolver(io);
  stream.connect(resolver.resolve(o.host, std::to_string(o.dashboard_port)));
  http::request<http::empty_body> req{http::verb::get, target, 11};
  // The dashboard answers only requests naming it (DNS-rebinding check).
  const bool v6 = o.host.find(':') != std::string::npos;
  req.set(http::field::host,
          (v6 ? "[" + o.host + "]" : o.host) + ":" + std::to_string(o.dashboard_port));
  req.set(http::field::user_agent, "rfsitl links");
  http::write(stream, req);
  beast::flat_buffer buffer;
  http::response_parser<http::string_body> parser;
  parser.body_limit(kMaxReplyBytes);
  http::read(stream, buffer, parser);
  beast::error_code ec;
  stream.socket().shutdown(asio::ip::tcp::socket::shutdown_both, ec);
  const auto& res = parser.get();
  if (res.result() != http::status::ok) {
    throw std::runtime_error("the dashboard answered " + std::to_string(res.result_int()) + ": " +
                             res.body());
  }
  return res.body();
}

int run_links(const LinksOptions& o) {
  std::string target = "/api/links?payload=" + std::to_string(o.size);
  if (o.top > 0) target += "&top=" + std::to_string(o.top);
  if (o.worst > 0) target += "&worst=" + std::to_string(o.worst);
  if (o.min_snr_db) target += "&min_snr_db=" + std::to_string(*o.min_snr_db);
  std::string body;
  try {
    body = http_get(o, target);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rfsitl links: %s:%u: %s (is `rfsitl run` serving its dashboard there?)\n",
                 o.host.c_str(), unsigned{o.dashboard_port}, e.what());
    return 1;
  }
  std::string error;
  const std::optional<std::string> table = monitor::link_table_text(body, error);
  if (!table) {
    std::fprintf(stderr, "rfsitl links: %s:%u answered, but %s\n", o.host.c_str(),
                 unsigned{o.dashboard_port}, error.c_str());
    return 1;
  }
  std::fputs(o.json ? (body + "\n").c_str() : table->c_str(), stdout);
  return 0;
}

}  // namespace

std::function<int()> add_links_command(CLI::App& parent) {
  auto opts = std::make_shared<LinksOptions>();
  CLI::App* cmd = parent.add_subcommand(
      "links",
      "Print the live link table of a running emulator: per link tx -> rx its distance, path "
      "gain, SNR, PER estimate and frames delivered / lost");
  cmd->add_option("--host", opts->host, "Emulator address")->capture_default_str();
  cmd->add_option("--dashboard-port", opts->dashboard_port,
                  "The emulator's dashboard port (rfsitl run prints it)")
      ->capture_default_str();
  auto* top = cmd->add_option("--top", opts->top, "Only the K links of highest SNR, best first")
                  ->check(CLI::Range(1, 65535));
  cmd->add_option("--worst", opts->worst,
                  "Only the K links of lowest SNR (among links that exist), worst first")
      ->check(CLI::Range(1, 65535))
      ->excludes(top);
  cmd->add_option("--min-snr", opts->min_snr_db, "Only links with at least this SNR (dB)");
  cmd->add_option("--size", opts->size, "Payload bytes the PER is estimated for")
      ->check(CLI::Range(1, 65535))
      ->capture_default_str();
  cmd->add_option("--timeout", opts->timeout_s, "Seconds to wait for the emulator")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_flag("--json", opts->json, "Print the emulator's JSON document (GET /api/links)");
  return [opts] { return run_links(*opts); };
}

}  // namespace rfsitl::app
