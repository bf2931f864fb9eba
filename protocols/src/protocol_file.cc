// Reading and parsing a protocol file.
#include "burrlab/protocols/protocol_file.h"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>
#include <utility>

namespace burrlab::protocols {

Result<LoadedProtocol> LoadProtocol(const std::string& path) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) return Error{fmt::format("cannot read {}: {}", path, ec.message())};
  if (size > kMaxProtocolBytes) {
    return Error{fmt::format(
        "{}: error: the file is {} bytes; protocol files are limited to {} "
        "bytes",
        path, size, kMaxProtocolBytes)};
  }
  std::ifstream file(path, std::ios::binary);
  if (!file) return Error{fmt::format("cannot read {}", path)};
  std::ostringstream text;
  text << file.rdbuf();
  return ParseLoadedProtocol(path, text.str());
}

Result<LoadedProtocol> ParseLoadedProtocol(const std::string& path,
                                           std::string text) {
  LoadedProtocol loaded;
  loaded.path = path;
  loaded.text = std::move(text);
  ParseOutcome parsed = ParseProtocol(path, loaded.text);
  if (!parsed.protocol.has_value()) {
    std::string all = FormatDiagnostics(path, loaded.text, parsed.diagnostics);
    if (!all.empty() && all.back() == '\n') all.pop_back();
    return Error{all};
  }
  loaded.protocol = std::move(*parsed.protocol);
  return loaded;
}

}  // namespace burrlab::protocols
