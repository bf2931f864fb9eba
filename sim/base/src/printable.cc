// Escaping untrusted text for messages.
#include "burrlab/base/printable.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>

namespace burrlab {
namespace {

// Length of the well-formed UTF-8 sequence starting `text` and its code
// point; 0 when the first byte does not start one (a stray continuation byte,
// an overlong form, a surrogate, beyond U+10FFFF or cut short).
std::size_t Utf8Length(std::string_view text, std::uint32_t* code) {
  const auto b0 = static_cast<unsigned char>(text[0]);
  std::size_t length = 0;
  if (b0 < 0x80) {
    *code = b0;
    return 1;
  } else if ((b0 & 0xe0) == 0xc0) {
    length = 2;
    *code = b0 & 0x1fu;
  } else if ((b0 & 0xf0) == 0xe0) {
    length = 3;
    *code = b0 & 0x0fu;
  } else if ((b0 & 0xf8) == 0xf0) {
    length = 4;
    *code = b0 & 0x07u;
  } else {
    return 0;
  }
  if (text.size() < length) return 0;
  for (std::size_t k = 1; k < length; ++k) {
    const auto b = static_cast<unsigned char>(text[k]);
    if ((b & 0xc0) != 0x80) return 0;
    *code = (*code << 6) | (b & 0x3fu);
  }
  constexpr std::uint32_t kMinCode[] = {0, 0, 0x80, 0x800, 0x10000};
  if (*code < kMinCode[length] || *code > 0x10ffff ||
      (*code >= 0xd800 && *code <= 0xdfff)) {
    return 0;
  }
  return length;
}

// The first code point of non-empty `text` as PrintableText writes it, and
// the bytes it spans.
struct PrintableChar {
  std::string text;       // as printed
  std::size_t bytes = 0;  // input bytes consumed
};
PrintableChar FirstPrintableChar(std::string_view text) {
  if (text.empty()) return {};
  std::uint32_t code = 0;
  const std::size_t length = Utf8Length(text, &code);
  if (length == 0) {
    return {fmt::format("\\x{:02x}", static_cast<unsigned char>(text[0])), 1};
  }
  if (code < 0x20 || code == 0x7f) {
    return {fmt::format("\\x{:02x}", code), 1};
  }
  if (code >= 0x80 && code <= 0x9f) {
    return {fmt::format("\\u{:04x}", code), length};
  }
  return {std::string(text.substr(0, length)), length};
}

// Most code points of a quoted source line; a longer one is cut to a window
// around the column.
constexpr int kMaxQuotedColumns = 160;

}  // namespace

std::string PrintableText(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  std::size_t i = 0;
  while (i < text.size()) {
    // Runs of printable ASCII are the common case: copied whole.
    std::size_t j = i;
    while (j < text.size() && text[j] >= 0x20 && text[j] < 0x7f) ++j;
    out.append(text.substr(i, j - i));
    if (j == text.size()) break;
    const PrintableChar c = FirstPrintableChar(text.substr(j));
    out += c.text;
    i = j + c.bytes;
  }
  return out;
}

std::string QuoteLineWithCaret(std::string_view line, int column) {
  // Columns [first, first + kMaxQuotedColumns) are shown.
  const int first = std::max(1, column - kMaxQuotedColumns / 2);
  std::string out, caret;
  if (first > 1) {
    out += "...";
    caret += "   ";
  }
  int at = 1;
  std::size_t i = 0;
  for (; i < line.size() && at < first + kMaxQuotedColumns; ++at) {
    const PrintableChar c = FirstPrintableChar(line.substr(i));
    if (at >= first) {
      if (line[i] == '\t') {
        out += '\t';
        if (at < column) caret += '\t';
      } else {
        out += c.text;
        const bool escaped = c.text != line.substr(i, c.bytes);
        if (at < column) caret.append(escaped ? c.text.size() : 1, ' ');
      }
    }
    i += c.bytes;
  }
  if (i < line.size()) out += "...";
  for (; at < column; ++at) {
    if (at >= first) caret += ' ';
  }
  return out + '\n' + caret + '^';
}

}  // namespace burrlab
