// "Did you mean": which names count as close to what was typed.
#include "burrlab/base/spelling.h"

#include <gtest/gtest.h>

#include <string_view>
#include <vector>

namespace burrlab {
namespace {

const std::vector<std::string_view> kCommands = {"demo", "sim", "help"};

TEST(EditDistance, CountsInsertDeleteReplaceAndAdjacentSwapAsOneEach) {
  EXPECT_EQ(EditDistance("demo", "demo"), 0u);
  EXPECT_EQ(EditDistance("dmeo", "demo"), 1u);       // swap
  EXPECT_EQ(EditDistance("desent", "descent"), 1u);  // insert
  EXPECT_EQ(EditDistance("descent", "desent"), 1u);  // delete
  EXPECT_EQ(EditDistance("bench", "bunch"), 1u);     // replace
  EXPECT_EQ(EditDistance("", "sim"), 3u);
  EXPECT_EQ(EditDistance("kitten", "sitting"), 3u);
}

TEST(DidYouMean, SuggestsTheNameWithinTwoEdits) {
  EXPECT_EQ(DidYouMean("dmeo", kCommands), "demo");
  EXPECT_EQ(DidYouMean("smi", kCommands), "sim");
  EXPECT_EQ(DidYouMean("hlep", kCommands), "help");
}

TEST(DidYouMean, SuggestsTheNameThatStartsWithWhatWasTyped) {
  EXPECT_EQ(DidYouMean("de", kCommands), "demo");
}

TEST(DidYouMean, SuggestsNothingWhenNothingIsClose) {
  EXPECT_EQ(DidYouMean("xyzzy", kCommands), "");
  EXPECT_EQ(DidYouMean("", kCommands), "");
}

TEST(DidYouMean, ShortWordsNeedFewerEditsThanTheirLength) {
  // "hi" is two edits from "sim", which is every character of it.
  EXPECT_EQ(DidYouMean("hi", kCommands), "");
}

}  // namespace
}  // namespace burrlab
