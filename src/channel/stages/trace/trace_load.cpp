// Reading a trace's files: where they are, how big, which format.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <span>
#include <stdexcept>
#include <string>
#include <system_error>

#include "rfsitl/channel/stages/trace.hpp"
#include "trace_text.hpp"

namespace rfsitl::channel::trace {
namespace {

std::string resolve(const std::string& source_dir, const std::string& file) {
  const std::filesystem::path p(file);
  if (p.is_absolute() || source_dir.empty()) return file;
  return (std::filesystem::path(source_dir) / p).string();
}

/// The whole file, refused before reading when it is over kMaxFileBytes.
std::string read_file(const std::string& path) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) throw std::invalid_argument(path + ": cannot read: " + ec.message());
  if (size > kMaxFileBytes) {
    throw std::invalid_argument(path + ": " + std::to_string(size) +
                                " bytes, more than the 256 MiB a trace file may have");
  }
  std::ifstream in(path, std::ios::binary);
  std::string bytes(static_cast<std::size_t>(size), '\0');
  if (!in || !in.read(bytes.data(), static_cast<std::streamsize>(size))) {
    throw std::invalid_argument(path + ": cannot read it whole");
  }
  return bytes;
}

}  // namespace

Trace load(const TraceSettings& settings, const std::string& source_dir,
           std::span<const NodeId> node_ids) {
  const std::string path = resolve(source_dir, settings.file);
  const std::string ext = detail::extension(settings.file);
  if (ext == ".csv") return parse_csv(read_file(path), path, node_ids);
  if (ext != ".npy") {
    throw std::invalid_argument(path +
                                ": unknown trace format (the name must end in .csv or .npy)");
  }
  const std::string links_path = resolve(source_dir, settings.links_file);
  const std::vector<LinkIds> links = parse_links_csv(read_file(links_path), links_path, node_ids);
  const std::string bytes = read_file(path);
  return parse_npy(std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()),
                   path, links, settings.step_s);
}

}  // namespace rfsitl::channel::trace
