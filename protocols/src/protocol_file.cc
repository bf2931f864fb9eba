// Reading and parsing a protocol file.
#include "burrlab/protocols/protocol_file.h"

#include <fmt/format.h>

#include <string>
#include <utility>
#include <variant>

#include "burrlab/base/file_text.h"

namespace burrlab::protocols {

Result<LoadedProtocol> LoadProtocol(const std::string& path) {
  std::variant<std::string, FileReadFailure> read =
      ReadFileBytes(path, kMaxProtocolBytes);
  if (std::string* text = std::get_if<std::string>(&read)) {
    return ParseLoadedProtocol(path, std::move(*text));
  }
  const FileReadFailure& failure = std::get<FileReadFailure>(read);
  if (failure.problem == FileProblem::kTooLarge) {
    return Error{fmt::format(
        "{}: error: the file is {} bytes; protocol files are limited to {} "
        "bytes",
        path, failure.size, kMaxProtocolBytes)};
  }
  return Error{failure.reason.empty()
                   ? fmt::format("cannot read {}", path)
                   : fmt::format("cannot read {}: {}", path, failure.reason)};
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
  loaded.notes = FormatDiagnostics(path, loaded.text, parsed.notes);
  return loaded;
}

}  // namespace burrlab::protocols
