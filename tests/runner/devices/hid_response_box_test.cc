// The hidapi backend against an emulated hidraw device (umockdev; ctest runs
// this binary under umockdev-wrapper): hidapi enumerates and opens it, the
// test writes input reports into its device node, and removes and re-adds it
// for unplug and re-plug. The station controller turns presses into responses.
#include "devices/hid_response_box.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <linux/hidraw.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <umockdev.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "station/station_controller.h"

namespace burrlab::runner {
namespace {

// A two-button box: one input report of one byte, bit 0 = button 1.
constexpr std::uint8_t kDescriptor[] = {
    0x05, 0x01, 0x09, 0x05, 0xA1, 0x01, 0x05, 0x09, 0x19, 0x01, 0x29, 0x08,
    0x15, 0x00, 0x25, 0x01, 0x75, 0x01, 0x95, 0x08, 0x81, 0x02, 0xC0};

// The kernel's answer to HIDIOCGRDESCSIZE, which hid_open_path asks.
gboolean OnIoctl(UMockdevIoctlBase*, UMockdevIoctlClient* client, gpointer) {
  if (umockdev_ioctl_client_get_request(client) == HIDIOCGRDESCSIZE) {
    GError* error = nullptr;
    UMockdevIoctlData* data = umockdev_ioctl_data_resolve(
        umockdev_ioctl_client_get_arg(client), 0, sizeof(int), &error);
    if (data != nullptr) {
      const int size = sizeof(kDescriptor);
      std::memcpy(data->data, &size, sizeof(size));
    }
    umockdev_ioctl_client_complete(client, 0, 0);
  } else {
    umockdev_ioctl_client_complete(client, -1, ENOTTY);
  }
  return TRUE;
}

class HidBoxTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const char* preload = std::getenv("LD_PRELOAD");
    if (preload == nullptr ||
        std::strstr(preload, "libumockdev-preload") == nullptr) {
      GTEST_SKIP() << "not under umockdev-wrapper: run this test through "
                      "ctest (Debian package umockdev)";
    }
    bed_ = umockdev_testbed_new();
    usb_ = umockdev_testbed_add_device(
        bed_, "usb", "usb1", nullptr, "idVendor", "16c0", "idProduct", "05df",
        "manufacturer", "Lab", "product", "Response box", "serial", "RB7",
        nullptr, "DEVTYPE", "usb_device", nullptr);
    hid_ = umockdev_testbed_add_device(
        bed_, "hid", "0003:16C0:05DF.0001", usb_, nullptr, "HID_ID",
        "0003:000016C0:000005DF", "HID_NAME", "Lab Response box", "HID_UNIQ",
        "RB7", nullptr);
    std::vector<guint8> descriptor(std::begin(kDescriptor),
                                   std::end(kDescriptor));
    umockdev_testbed_set_attribute_binary(bed_, hid_, "report_descriptor",
                                          descriptor.data(),
                                          static_cast<gint>(descriptor.size()));
    ioctl_ = umockdev_ioctl_base_new();
    g_signal_connect(ioctl_, "handle-ioctl",
                     reinterpret_cast<GCallback>(&OnIoctl), nullptr);
    GError* error = nullptr;
    ASSERT_TRUE(
        umockdev_testbed_attach_ioctl(bed_, "/dev/hidraw0", ioctl_, &error));
    PlugIn();
  }

  void TearDown() override {
    if (bed_ == nullptr) return;
    if (writer_ >= 0) close(writer_);
    g_object_unref(ioctl_);
    g_object_unref(bed_);
    g_free(usb_);
    g_free(hid_);
    g_free(raw_);
  }

  // The hidraw node: sysfs entry and a FIFO as its /dev file, so reads block
  // and poll like the kernel's (umockdev's default node is a plain file).
  void PlugIn() {
    g_free(raw_);
    raw_ = umockdev_testbed_add_device(bed_, "hidraw", "hidraw0", hid_, "dev",
                                       "241:0", nullptr, "DEVNAME",
                                       "/dev/hidraw0", nullptr);
    umockdev_testbed_set_attribute_link(bed_, raw_, "device", "..");
    node_ = std::string(umockdev_testbed_get_root_dir(bed_)) + "/dev/hidraw0";
    ASSERT_EQ(mkfifo(node_.c_str(), 0600), 0);
  }

  void Unplug() {
    if (writer_ >= 0) close(writer_);
    writer_ = -1;
    umockdev_testbed_remove_device(bed_, raw_);
    unlink(node_.c_str());
  }

  // Writes one input report, as the box sends when a button changes.
  void Send(std::uint8_t buttons) {
    if (writer_ < 0) writer_ = open(node_.c_str(), O_WRONLY);
    ASSERT_GE(writer_, 0);
    ASSERT_EQ(write(writer_, &buttons, 1), 1);
  }

  // Waits up to 2 s for at least `count` events.
  std::vector<HidEvent> WaitFor(HidResponseBox& box, std::size_t count) {
    std::vector<HidEvent> all;
    for (int i = 0; i < 200 && all.size() < count; ++i) {
      for (HidEvent& e : box.TakeEvents()) all.push_back(std::move(e));
      if (all.size() < count) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
      }
    }
    return all;
  }

  static HidBoxOptions Options() {
    HidBoxOptions o;
    o.vendor_id = 0x16c0;
    o.product_id = 0x05df;
    o.buttons = {{1, "1"}, {2, "2"}};
    return o;
  }

  UMockdevTestbed* bed_ = nullptr;
  UMockdevIoctlBase* ioctl_ = nullptr;
  gchar* usb_ = nullptr;
  gchar* hid_ = nullptr;
  gchar* raw_ = nullptr;
  std::string node_;
  int writer_ = -1;
};

TEST_F(HidBoxTest, EnumeratesTheBoxWithItsIds) {
  const std::vector<HidDeviceInfo> all = ListHidDevices();
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].path, "/dev/hidraw0");
  EXPECT_EQ(all[0].vendor_id, 0x16c0);
  EXPECT_EQ(all[0].product_id, 0x05df);
  EXPECT_EQ(all[0].serial, "RB7");
  EXPECT_EQ(all[0].product, "Response box");
}

TEST_F(HidBoxTest, APressBecomesAResponseWithItsArrivalTime) {
  Result<std::unique_ptr<HidResponseBox>> box = HidResponseBox::Open(Options());
  ASSERT_TRUE(box.ok()) << box.error().message;
  EXPECT_TRUE((*box)->connected());

  protocols::TrialSpec trial;
  trial.trial_index = 0;
  trial.block = "box";
  trial.question = "Which interval felt stiffer?";
  trial.response_options = {"1", "2"};
  StationController station(1, "hid", 0.0);
  station.BeginTrial(trial, 0);
  const double asked_s = static_cast<double>(MonotonicNowNs()) * 1e-9;
  (void)station.OnInput("SPACE", asked_s);  // no intervals: straight to it
  ASSERT_EQ(station.phase(), StationPhase::kResponse);

  const std::int64_t before_ns = MonotonicNowNs();
  // A FIFO is a byte stream, not hidraw's one report per read: each report
  // is read before the next is sent (a real press lasts >= 50 ms anyway).
  Send(0b10);  // button 2 down
  std::vector<HidEvent> events = WaitFor(**box, 1);
  const std::int64_t after_ns = MonotonicNowNs();
  Send(0b00);  // and up
  for (HidEvent& e : WaitFor(**box, 1)) events.push_back(std::move(e));
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].kind, HidEvent::Kind::kPress);
  EXPECT_EQ(events[0].button, 2);
  EXPECT_EQ(events[0].key, "2");
  EXPECT_GE(events[0].time_ns, before_ns);
  EXPECT_LE(events[0].time_ns, after_ns);
  EXPECT_EQ(events[1].kind, HidEvent::Kind::kRelease);

  const double pressed_s = static_cast<double>(events[0].time_ns) * 1e-9;
  const std::optional<protocols::Response> r =
      station.OnInput(events[0].key, pressed_s);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->answer, "2");
  EXPECT_NEAR(*r->response_time_s, pressed_s - asked_s, 1e-9);
}

TEST_F(HidBoxTest, AnUnplugMidTrialAbortsItPausesAndLosesNothing) {
  Result<std::unique_ptr<HidResponseBox>> opened =
      HidResponseBox::Open(Options());
  ASSERT_TRUE(opened.ok()) << opened.error().message;
  HidResponseBox& box = **opened;
  protocols::TrialSpec trial;
  trial.question = "Which interval felt stiffer?";
  trial.response_options = {"1", "2"};
  trial.intervals.resize(2);
  for (auto& i : trial.intervals) i.duration_s = 5.0;
  StationController station(2, "hid", 0.0);
  std::vector<protocols::Response> answers;  // what the journal would hold

  // Trial 1 is answered with button 1.
  station.BeginTrial(trial, 0);
  (void)station.OnInput("SPACE", 0.0);
  station.Advance(10.0);
  Send(0b01);
  std::vector<HidEvent> events = WaitFor(box, 1);
  ASSERT_EQ(events.size(), 1u);
  std::optional<protocols::Response> r = station.OnInput(events[0].key, 11.0);
  ASSERT_TRUE(r.has_value());
  answers.push_back(*r);
  Send(0b00);
  ASSERT_EQ(WaitFor(box, 1).size(), 1u);

  // Trial 2: the box goes away during the first interval.
  trial.trial_index = 1;
  station.BeginTrial(trial, 1);
  (void)station.OnInput("SPACE", 20.0);
  Unplug();
  events = WaitFor(box, 1);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].kind, HidEvent::Kind::kUnplugged);
  EXPECT_EQ(events[0].reason, "the device node /dev/hidraw0 is gone");
  EXPECT_FALSE(box.connected());
  station.SetDeviceState("unplugged: " + events[0].reason);
  station.Pause("the response box was unplugged; reconnect it to go on");
  EXPECT_TRUE(station.trial_aborted());
  EXPECT_EQ(station.phase(), StationPhase::kPaused);
  EXPECT_EQ(station.frame().subject.message,
            "Paused: the response box was unplugged; reconnect it to go on");
  ASSERT_EQ(answers.size(), 1u);  // trial 1 is kept
  EXPECT_EQ(answers[0].answer, "1");
  const Status missing = box.Reconnect();
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().message, "hid: no device 16c0:05df is connected");

  // Plugged in again: the same trial runs from its start.
  PlugIn();
  const Status back = box.Reconnect();
  ASSERT_TRUE(back.ok()) << back.error().message;
  events = WaitFor(box, 1);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].kind, HidEvent::Kind::kReplugged);
  station.SetDeviceState("ok");
  station.Resume();
  (void)station.OnInput("SPACE", 30.0);
  station.Advance(40.0);
  Send(0b10);
  events = WaitFor(box, 1);
  ASSERT_EQ(events.size(), 1u);
  r = station.OnInput(events[0].key, 41.5);
  ASSERT_TRUE(r.has_value());
  answers.push_back(*r);
  ASSERT_EQ(answers.size(), 2u);
  EXPECT_EQ(answers[1].answer, "2");
  EXPECT_NEAR(*answers[1].response_time_s, 1.5, 1e-9);
}

TEST_F(HidBoxTest, ABoxThatIsNotThereIsNamed) {
  HidBoxOptions o = Options();
  o.product_id = 0x0001;
  Result<std::unique_ptr<HidResponseBox>> box = HidResponseBox::Open(o);
  ASSERT_FALSE(box.ok());
  EXPECT_EQ(box.error().message, "hid: no device 16c0:0001 is connected");
}

TEST(HidBoxOptions, NamesTheRuleBroken) {
  HidBoxOptions o;
  EXPECT_EQ(o.Validate().error().message,
            "hid: vendor_id and product_id are required (got 0000:0000)");
  o.vendor_id = 1;
  o.product_id = 2;
  EXPECT_EQ(o.Validate().error().message, "hid: the button mapping is empty");
  o.buttons = {{1, "1"}, {1, "2"}};
  EXPECT_EQ(o.Validate().error().message, "hid: button 1 is mapped twice");
  o.buttons = {{0, "1"}};
  EXPECT_EQ(o.Validate().error().message, "hid: button 0 is outside 1-512");
  o.buttons = {{3, ""}};
  EXPECT_EQ(o.Validate().error().message, "hid: button 3 has no key");
  o.buttons = {{3, "S"}};
  EXPECT_TRUE(o.Validate().ok());
}

}  // namespace
}  // namespace burrlab::runner
