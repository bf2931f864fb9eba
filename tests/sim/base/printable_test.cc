// Untrusted text in messages: what is escaped (the exact text) and what
// passes unchanged.
#include "burrlab/base/printable.h"

#include <gtest/gtest.h>

#include <string>

namespace burrlab {
namespace {

TEST(PrintableText, EscapesControlBytesAndDel) {
  EXPECT_EQ(PrintableText("a\x1b[31mb\x07"), "a\\x1b[31mb\\x07");
  EXPECT_EQ(PrintableText(std::string("nul\0tab\tnl\ncr\r", 14)),
            "nul\\x00tab\\x09nl\\x0acr\\x0d");
  EXPECT_EQ(PrintableText("del\x7f"), "del\\x7f");
}

TEST(PrintableText, EscapesC1ControlsAndBytesThatAreNotUtf8) {
  EXPECT_EQ(PrintableText("csi\xc2\x9b"
                          "31m"),
            "csi\\u009b31m");  // U+009B
  EXPECT_EQ(PrintableText("bad\xff\xfe"), "bad\\xff\\xfe");
  EXPECT_EQ(PrintableText("cut\xe2\x82"), "cut\\xe2\\x82");  // truncated
  EXPECT_EQ(PrintableText("overlong\xc0\xaf"), "overlong\\xc0\\xaf");
  EXPECT_EQ(PrintableText("surrogate\xed\xa0\x80"), "surrogate\\xed\\xa0\\x80");
}

TEST(PrintableText, KeepsPrintableUtf8AndIsIdempotent) {
  const std::string text = "c\xc3\xa9 \xe2\x82\xac \xf0\x9f\x99\x82 \\x1b";
  EXPECT_EQ(PrintableText(text), text);
  const std::string once = PrintableText("a\x1b\xff");
  EXPECT_EQ(PrintableText(once), once);
}

TEST(QuoteLineWithCaret, CaretCountsCodePointsAndEscapeWidths) {
  EXPECT_EQ(QuoteLineWithCaret("a = 1", 5), "a = 1\n    ^");
  EXPECT_EQ(QuoteLineWithCaret("\tb\t= x", 4), "\tb\t= x\n\t \t^");
  // The ESC becomes four characters, so the caret moves by four.
  EXPECT_EQ(QuoteLineWithCaret("k\x1bx = 1", 4), "k\\x1bx = 1\n      ^");
  // A two-byte character is one column.
  EXPECT_EQ(QuoteLineWithCaret("\xc3\xa9 = 1", 3), "\xc3\xa9 = 1\n  ^");
}

TEST(QuoteLineWithCaret, CutsALongLineToAWindowAroundTheColumn) {
  const std::string line =
      std::string(1000, 'x') + "!" + std::string(1000, 'y');
  const std::string quoted = QuoteLineWithCaret(line, 1001);
  EXPECT_EQ(quoted, "..." + std::string(80, 'x') + "!" + std::string(79, 'y') +
                        "...\n" + std::string(83, ' ') + "^");
}

}  // namespace
}  // namespace burrlab
