// Untrusted text made safe to print: a protocol, station, material or data
// file may hold any bytes, and an error message that quotes them must not let
// an ESC or BEL reach the terminal (escape-sequence injection) or break the
// message's line. A generic utility kept at the root of the dependency graph,
// like spelling.h, so every library's messages can use it.
#ifndef BURRLAB_BASE_PRINTABLE_H_
#define BURRLAB_BASE_PRINTABLE_H_

#include <cstddef>
#include <string>
#include <string_view>

namespace burrlab {

// `text` with everything that is not printable escaped: C0 control bytes
// (0x00-0x1f, tab and line breaks included) and DEL as \xNN (ESC is \x1b),
// C1 control characters (U+0080-U+009F, which some terminals obey) as \u00NN,
// and bytes that are not well-formed UTF-8 as \xNN. Well-formed UTF-8
// otherwise passes unchanged; backslashes are not escaped, so escaping twice
// changes nothing.
std::string PrintableText(std::string_view text);

// A source line quoted under a diagnostic: `line` (without its line break)
// made printable, '\n', and a caret under code point `column` (1-based; an
// escaped character moves it by the width of its escape). Tabs are kept in
// the line and copied into the caret line, so the caret lines up in a
// terminal. A line longer than 160 code points is cut to a window around the
// column, marked with "...". No final line break.
std::string QuoteLineWithCaret(std::string_view line, int column);

}  // namespace burrlab

#endif  // BURRLAB_BASE_PRINTABLE_H_
