// The libusb transport without a Falcon: opening says which USB id it looked
// for (this machine has no USB bus; a Falcon plugged in skips the test).
#include "devices/libusb_transport.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace burrlab::runner::falcon {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;

TEST(LibusbTransport, OpeningWithoutAFalconNamesTheUsbId) {
  const Result<int> count = LibusbTransport::CountFalcons();
  if (count.ok() && *count > 0) GTEST_SKIP() << "a Falcon is plugged in";
  const auto transport = LibusbTransport::Open(0);
  ASSERT_FALSE(transport.ok());
  EXPECT_THAT(transport.error().message, StartsWith("Falcon: "));
  if (count.ok()) {
    EXPECT_EQ(transport.error().message,
              "Falcon: no Novint Falcon (USB 0403:cb48) number 0 on the bus "
              "(0 found)");
  } else {
    EXPECT_THAT(transport.error().message, HasSubstr("libusb"));
  }
}

}  // namespace
}  // namespace burrlab::runner::falcon
