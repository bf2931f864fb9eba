// Reading a protocol file: its text (at most kMaxProtocolBytes) parsed into a
// Protocol, or every diagnostic formatted as `burrlab validate` prints them.
#ifndef BURRLAB_PROTOCOLS_PROTOCOL_FILE_H_
#define BURRLAB_PROTOCOLS_PROTOCOL_FILE_H_

#include <string>

#include "burrlab/base/result.h"
#include "burrlab/protocols/protocol.h"

namespace burrlab::protocols {

// A protocol file read and parsed, with its text (for the journal's hash).
struct LoadedProtocol {
  std::string path;  // as given
  std::string text;
  Protocol protocol;
  // The parser's notes formatted as `burrlab validate` prints them (each
  // "path:line:col: note: ...", its line and a caret), or empty; the
  // commands print them on stderr before they go on.
  std::string notes;
};

// Reads and parses a protocol file; the error holds every diagnostic
// formatted as `burrlab validate` prints them. A file that cannot be read
// gives "cannot read <path>: <reason>" (or "cannot read <path>"); one larger
// than kMaxProtocolBytes is refused unread ("<path>: error: the file is N
// bytes; protocol files are limited to 1048576 bytes").
Result<LoadedProtocol> LoadProtocol(const std::string& path);
// The same for a protocol's text (e.g. one compiled in); `path` names it in
// diagnostics and the journal.
Result<LoadedProtocol> ParseLoadedProtocol(const std::string& path,
                                           std::string text);

}  // namespace burrlab::protocols

#endif  // BURRLAB_PROTOCOLS_PROTOCOL_FILE_H_
