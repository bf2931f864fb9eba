// Error lines stay on one line whatever the message holds.
#include "cli/command_table.h"  // private to burrlab::runner

#include <gtest/gtest.h>

#include <sstream>

namespace burrlab::runner {
namespace {

TEST(OneLine, JoinsLinesWithOneSpaceAndTrims) {
  EXPECT_EQ(OneLine("  first\nsecond\r\n\tthird \n"), "first second third");
  EXPECT_EQ(OneLine("\n\n"), "");
}

TEST(Fail, PrintsOneBurrlabLineAndReturnsOne) {
  std::ostringstream err;
  EXPECT_EQ(Fail(err, "bad --x\nvalue"), 1);
  EXPECT_EQ(err.str(), "burrlab: bad --x value\n");
}

}  // namespace
}  // namespace burrlab::runner
