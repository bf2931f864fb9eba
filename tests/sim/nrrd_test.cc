// NRRD reading: round trips of hand-built files (8/16-bit, signed/unsigned,
// little/big endian, raw/gzip), voxel size from spacings or space directions,
// intensity mappings, and the exact one-line error of each refused file.
#include "burrlab/sim/nrrd.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "gzip_for_tests.h"

namespace burrlab::sim {
namespace {

using testing::Gzip;

// An NRRD0004 file: magic, the given header lines, a blank line, the data.
std::string Nrrd(const std::string& fields, const std::string& data) {
  return "NRRD0004\n" + fields + "\n" + data;
}

// The 8-bit test volume 4 x 3 x 2: voxel (i, j, k) holds i + 4 j + 12 k + 1.
std::string Ramp8() {
  std::string data;
  for (int v = 0; v < 24; ++v) data += static_cast<char>(v + 1);
  return data;
}

// 16-bit samples in the given byte order.
std::string Samples16(const std::vector<int>& values, bool big_endian) {
  std::string data;
  for (int value : values) {
    const auto bits = static_cast<std::uint16_t>(value);
    const char hi = static_cast<char>(bits >> 8);
    const char lo = static_cast<char>(bits & 0xff);
    data += big_endian ? std::string{hi, lo} : std::string{lo, hi};
  }
  return data;
}

IntensityMapping Linear(double low, double high) {
  IntensityMapping mapping;
  mapping.kind = IntensityMapping::Kind::kLinear;
  mapping.low = low;
  mapping.high = high;
  return mapping;
}

IntensityMapping Threshold(double threshold) {
  IntensityMapping mapping;
  mapping.kind = IntensityMapping::Kind::kThreshold;
  mapping.threshold = threshold;
  return mapping;
}

const std::string kRaw8Header =
    "type: uchar\ndimension: 3\nsizes: 4 3 2\nencoding: raw\n";

// The error message of parsing `bytes` as "scan.nrrd", or "ok".
std::string ErrorOf(const std::string& bytes,
                    const IntensityMapping& mapping = IntensityMapping{}) {
  Result<Volume> volume = ParseNrrd("scan.nrrd", bytes, mapping);
  return volume.ok() ? "ok" : volume.error().message;
}

TEST(Nrrd, Raw8BitRoundTripsInXFastestOrder) {
  Result<Volume> volume =
      ParseNrrd("scan.nrrd", Nrrd(kRaw8Header, Ramp8()), Linear(0, 255));
  ASSERT_TRUE(volume.ok()) << volume.error().message;
  EXPECT_EQ(volume->nx(), 4);
  EXPECT_EQ(volume->ny(), 3);
  EXPECT_EQ(volume->nz(), 2);
  EXPECT_EQ(volume->voxel_mm(), 0.3);  // no spacing given
  for (int k = 0; k < 2; ++k) {
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i < 4; ++i) {
        EXPECT_EQ(volume->At(i, j, k), i + 4 * j + 12 * k + 1);
        EXPECT_EQ(volume->Label(i, j, k), 0);
      }
    }
  }
}

TEST(Nrrd, Raw16BitLittleAndBigEndianGiveTheSameVolume) {
  std::vector<int> values;
  for (int v = 0; v < 24; ++v) values.push_back(v * 400);  // 0 .. 9200
  for (const bool big : {false, true}) {
    const std::string header =
        std::string("type: ushort\ndimension: 3\n") +
        "sizes: 4 3 2\nencoding: raw\nendian: " + (big ? "big" : "little") +
        "\n";
    Result<Volume> volume = ParseNrrd(
        "scan.nrrd", Nrrd(header, Samples16(values, big)), Linear(0, 9200));
    ASSERT_TRUE(volume.ok()) << volume.error().message;
    for (int v = 0; v < 24; ++v) {
      EXPECT_EQ(volume->occupancy()[v], std::lround(255.0 * v / 23.0))
          << (big ? "big" : "little") << " endian, voxel " << v;
    }
  }
}

TEST(Nrrd, SignedSamplesAreReadAsNegativeIntensities) {
  // int16: -1000 and 1000 around a threshold of 0.
  const std::string header16 =
      "type: short\ndimension: 3\nsizes: 2 1 1\nencoding: raw\n"
      "endian: big\n";
  Result<Volume> v16 =
      ParseNrrd("scan.nrrd", Nrrd(header16, Samples16({-1000, 1000}, true)),
                Threshold(0));
  ASSERT_TRUE(v16.ok()) << v16.error().message;
  EXPECT_EQ(v16->At(0, 0, 0), 0);
  EXPECT_EQ(v16->At(1, 0, 0), 255);
  // int8: -128 .. 127 mapped linearly.
  const std::string header8 =
      "type: signed char\ndimension: 3\nsizes: 3 1 1\nencoding: raw\n";
  Result<Volume> v8 =
      ParseNrrd("scan.nrrd", Nrrd(header8, std::string{'\x80', '\x00', '\x7f'}),
                Linear(-128, 127));
  ASSERT_TRUE(v8.ok()) << v8.error().message;
  EXPECT_EQ(v8->At(0, 0, 0), 0);
  EXPECT_EQ(v8->At(1, 0, 0), 128);  // round(255 * 128 / 255)
  EXPECT_EQ(v8->At(2, 0, 0), 255);
}

TEST(Nrrd, GzipEncodedDataRoundTrips) {
  // 8-bit, "gzip" spelling.
  const std::string header8 =
      "type: uint8\ndimension: 3\nsizes: 4 3 2\nencoding: gzip\n";
  Result<Volume> v8 =
      ParseNrrd("scan.nrrd", Nrrd(header8, Gzip(Ramp8())), Linear(0, 255));
  ASSERT_TRUE(v8.ok()) << v8.error().message;
  for (int v = 0; v < 24; ++v) EXPECT_EQ(v8->occupancy()[v], v + 1);
  // 16-bit big endian, "gz" spelling.
  std::vector<int> values;
  for (int v = 0; v < 24; ++v) values.push_back(v * 10);
  const std::string header16 =
      "type: int16\ndimension: 3\nsizes: 4 3 2\nencoding: gz\nendian: big\n";
  Result<Volume> v16 =
      ParseNrrd("scan.nrrd", Nrrd(header16, Gzip(Samples16(values, true))),
                Linear(0, 230));
  ASSERT_TRUE(v16.ok()) << v16.error().message;
  for (int v = 0; v < 24; ++v) {
    EXPECT_EQ(v16->occupancy()[v], std::lround(255.0 * v * 10 / 230.0));
  }
}

TEST(Nrrd, ConcatenatedGzipMembersAreOneStream) {
  const std::string data = Ramp8();
  const std::string header =
      "type: uchar\ndimension: 3\nsizes: 4 3 2\nencoding: gzip\n";
  Result<Volume> volume =
      ParseNrrd("scan.nrrd",
                Nrrd(header, Gzip(data.substr(0, 10)) + Gzip(data.substr(10))),
                Linear(0, 255));
  ASSERT_TRUE(volume.ok()) << volume.error().message;
  for (int v = 0; v < 24; ++v) EXPECT_EQ(volume->occupancy()[v], v + 1);
}

TEST(Nrrd, SpacingsGiveTheVoxelSize) {
  Result<Volume> volume = ParseNrrd(
      "scan.nrrd", Nrrd(kRaw8Header + "spacings: 0.25 0.25 0.25\n", Ramp8()),
      Threshold(0.5));
  ASSERT_TRUE(volume.ok()) << volume.error().message;
  EXPECT_EQ(volume->voxel_mm(), 0.25);
  // Within 1 % the median is taken.
  Result<Volume> nearly = ParseNrrd(
      "scan.nrrd", Nrrd(kRaw8Header + "spacings: 0.301 0.3 0.2995\n", Ramp8()),
      Threshold(0.5));
  ASSERT_TRUE(nearly.ok()) << nearly.error().message;
  EXPECT_EQ(nearly->voxel_mm(), 0.3);
}

TEST(Nrrd, SpaceDirectionsGiveTheVoxelSize) {
  const std::string fields = kRaw8Header +
                             "space: right-anterior-superior\n"
                             "space directions: (0,0.4,0) (-0.4,0,0) "
                             "(0, 0, 0.4)\n"
                             "space origin: (-12.5,3,7)\n"
                             "space units: \"mm\" \"mm\" \"mm\"\n";
  Result<Volume> volume =
      ParseNrrd("scan.nrrd", Nrrd(fields, Ramp8()), Threshold(0.5));
  ASSERT_TRUE(volume.ok()) << volume.error().message;
  EXPECT_DOUBLE_EQ(volume->voxel_mm(), 0.4);
}

TEST(Nrrd, ThresholdMappingMakesSolidAtOrAboveTheThreshold) {
  const std::string header =
      "type: uchar\ndimension: 3\nsizes: 3 1 1\nencoding: raw\n";
  Result<Volume> volume =
      ParseNrrd("scan.nrrd", Nrrd(header, std::string{'\x63', '\x64', '\xff'}),
                Threshold(100));
  ASSERT_TRUE(volume.ok()) << volume.error().message;
  EXPECT_EQ(volume->At(0, 0, 0), 0);    // 99
  EXPECT_EQ(volume->At(1, 0, 0), 255);  // 100
  EXPECT_EQ(volume->At(2, 0, 0), 255);  // 255
}

TEST(Nrrd, LinearMappingScalesBetweenLowAndHigh) {
  const std::string header =
      "type: ushort\ndimension: 3\nsizes: 6 1 1\nencoding: raw\n"
      "endian: little\n";
  Result<Volume> volume =
      ParseNrrd("scan.nrrd",
                Nrrd(header, Samples16({50, 100, 200, 250, 300, 400}, false)),
                Linear(100, 300));
  ASSERT_TRUE(volume.ok()) << volume.error().message;
  EXPECT_EQ(volume->At(0, 0, 0), 0);    // below low
  EXPECT_EQ(volume->At(1, 0, 0), 0);    // at low
  EXPECT_EQ(volume->At(2, 0, 0), 128);  // round(127.5)
  EXPECT_EQ(volume->At(3, 0, 0), 191);  // round(191.25)
  EXPECT_EQ(volume->At(4, 0, 0), 255);  // at high
  EXPECT_EQ(volume->At(5, 0, 0), 255);  // above high
}

TEST(Nrrd, CommentsKeyValuesCrlfAndInformationalFieldsAreAccepted) {
  const std::string bytes =
      "NRRD0005\r\n"
      "# Complete NRRD file format specification at:\r\n"
      "# http://teem.sourceforge.net/nrrd/format.html\r\n"
      "TYPE: unsigned char\r\n"
      "dimension: 3\r\n"
      "content: temporal bone: left\r\n"
      "sizes: 4 3 2\r\n"
      "kinds: domain domain domain\r\n"
      "DICOM:0008:=CT\r\n"
      "scanner:=micro-CT: 20 um\r\n"
      "encoding: raw\r\n"
      "spacings: 0.5 0.5 0.5\r\n"
      "\r\n" +
      Ramp8();
  Result<Volume> volume = ParseNrrd("scan.nrrd", bytes, Linear(0, 255));
  ASSERT_TRUE(volume.ok()) << volume.error().message;
  EXPECT_EQ(volume->voxel_mm(), 0.5);
  EXPECT_EQ(volume->At(3, 2, 1), 24);
}

TEST(Nrrd, LineSkipAndByteSkipLocateTheData) {
  Result<Volume> skipped =
      ParseNrrd("scan.nrrd",
                Nrrd(kRaw8Header + "line skip: 2\nbyte skip: 3\n",
                     "junk line\n\nxyz" + Ramp8()),
                Linear(0, 255));
  ASSERT_TRUE(skipped.ok()) << skipped.error().message;
  EXPECT_EQ(skipped->At(0, 0, 0), 1);
  EXPECT_EQ(skipped->At(3, 2, 1), 24);
  // byte skip -1: the data are the last bytes of the file.
  Result<Volume> at_end = ParseNrrd(
      "scan.nrrd", Nrrd(kRaw8Header + "byte skip: -1\n", "padding" + Ramp8()),
      Linear(0, 255));
  ASSERT_TRUE(at_end.ok()) << at_end.error().message;
  EXPECT_EQ(at_end->At(0, 0, 0), 1);
}

TEST(Nrrd, BadMagicIsRefused) {
  EXPECT_EQ(ErrorOf("P5\n4 3\n255\n"),
            "scan.nrrd: not an NRRD file: first line is 'P5', expected "
            "NRRD0001 to NRRD0005");
  EXPECT_EQ(ErrorOf("NRRD0006\n" + kRaw8Header + "\n" + Ramp8()),
            "scan.nrrd: not an NRRD file: first line is 'NRRD0006', expected "
            "NRRD0001 to NRRD0005");
  EXPECT_EQ(ErrorOf(""),
            "scan.nrrd: not an NRRD file: first line is '', expected NRRD0001 "
            "to NRRD0005");
}

TEST(Nrrd, MissingSizesIsRefused) {
  EXPECT_EQ(ErrorOf(Nrrd("type: uchar\ndimension: 3\nencoding: raw\n", "")),
            "scan.nrrd: missing required field 'sizes'");
}

TEST(Nrrd, DimensionOtherThanThreeIsRefused) {
  EXPECT_EQ(ErrorOf(Nrrd("type: uchar\ndimension: 2\nsizes: 4 6\n"
                         "encoding: raw\n",
                         Ramp8())),
            "scan.nrrd: dimension: expected 3, got '2'");
}

TEST(Nrrd, UnsupportedTypeIsRefused) {
  EXPECT_EQ(ErrorOf(Nrrd("type: float\ndimension: 3\nsizes: 4 3 2\n"
                         "encoding: raw\nendian: little\n",
                         Ramp8())),
            "scan.nrrd: type: unsupported type 'float' (supported: 8- and "
            "16-bit integers)");
}

TEST(Nrrd, MalformedSizesAreRefused) {
  EXPECT_EQ(ErrorOf(Nrrd("type: uchar\ndimension: 3\nsizes: 12 x 4\n"
                         "encoding: raw\n",
                         Ramp8())),
            "scan.nrrd: sizes: expected 3 positive integers, got '12 x 4'");
  EXPECT_EQ(ErrorOf(Nrrd("type: uchar\ndimension: 3\nsizes: 4 0 2\n"
                         "encoding: raw\n",
                         Ramp8())),
            "scan.nrrd: sizes: expected 3 positive integers, got '4 0 2'");
}

TEST(Nrrd, OversizedSizesAreRefusedBeforeAllocating) {
  EXPECT_EQ(ErrorOf(Nrrd("type: uchar\ndimension: 3\n"
                         "sizes: 100000 100000 100000\nencoding: raw\n",
                         Ramp8())),
            "scan.nrrd: sizes: 100000 100000 100000 exceeds the limit of 2048 "
            "voxels per axis");
  EXPECT_EQ(ErrorOf(Nrrd("type: uchar\ndimension: 3\n"
                         "sizes: 2048 2048 2048\nencoding: raw\n",
                         Ramp8())),
            "scan.nrrd: sizes: 2048 2048 2048 is 8589934592 voxels, above the "
            "limit of 1073741824");
  // The largest allowed volume with a few bytes of data: refused from the
  // byte counts alone (allocating it would take 2 GiB).
  EXPECT_EQ(ErrorOf(Nrrd("type: ushort\ndimension: 3\n"
                         "sizes: 1024 1024 1024\nencoding: raw\n"
                         "endian: little\n",
                         Ramp8())),
            "scan.nrrd: raw data: expected 2147483648 bytes, got 24");
  EXPECT_EQ(ErrorOf(Nrrd("type: uchar\ndimension: 3\n"
                         "sizes: 1024 1024 1024\nencoding: gzip\n",
                         Gzip(std::string(1000, '\0')))),
            "scan.nrrd: gzip data: compressed stream is truncated (29 "
            "compressed bytes cannot hold 1073741824 bytes)");
}

TEST(Nrrd, TruncatedRawDataIsRefused) {
  EXPECT_EQ(ErrorOf(Nrrd(kRaw8Header, Ramp8().substr(0, 20))),
            "scan.nrrd: raw data: expected 24 bytes, got 20");
  EXPECT_EQ(ErrorOf(Nrrd(kRaw8Header, Ramp8() + "\n")),
            "scan.nrrd: raw data: expected 24 bytes, got 25");
}

TEST(Nrrd, TruncatedGzipStreamIsRefused) {
  std::string data;
  for (int v = 0; v < 512; ++v) data += static_cast<char>(v * 7);
  const std::string header =
      "type: uchar\ndimension: 3\nsizes: 8 8 8\nencoding: gzip\n";
  // Stored (level 0) deflate: 10 bytes of gzip header and 5 of block header
  // precede the samples, so cutting there leaves exactly 200 samples.
  const std::string stored = Gzip(data, 0);
  ASSERT_EQ(stored.size(), 10u + 5u + 512u + 8u);
  EXPECT_EQ(ErrorOf(Nrrd(header, stored.substr(0, 215))),
            "scan.nrrd: gzip data: compressed stream is truncated "
            "(decompressed 200 of 512 bytes)");
  // Cut inside the trailer: all samples, but no end of stream.
  EXPECT_EQ(ErrorOf(Nrrd(header, stored.substr(0, stored.size() - 3))),
            "scan.nrrd: gzip data: compressed stream is truncated "
            "(decompressed 512 of 512 bytes)");
  // Garbage after the stream and a stream that holds too much.
  EXPECT_EQ(ErrorOf(Nrrd(header, stored + "junk")),
            "scan.nrrd: gzip data: 4 bytes of trailing data after the "
            "compressed stream");
  EXPECT_EQ(ErrorOf(Nrrd(header, Gzip(data + "x"))),
            "scan.nrrd: gzip data: decompresses to more than the expected 512 "
            "bytes");
  EXPECT_EQ(ErrorOf(Nrrd(header, Gzip(data.substr(0, 500)))),
            "scan.nrrd: gzip data: decompressed to 500 bytes, expected 512");
  EXPECT_EQ(ErrorOf(Nrrd(header, "this is not gzip at all")),
            "scan.nrrd: gzip data: corrupt compressed stream ('incorrect "
            "header check')");
}

TEST(Nrrd, AnisotropicVoxelsAreRefused) {
  EXPECT_EQ(ErrorOf(Nrrd(kRaw8Header + "spacings: 0.3 0.3 0.6\n", Ramp8())),
            "scan.nrrd: spacings: voxels must be isotropic within 1 %, got 0.3 "
            "0.3 0.6 mm");
  EXPECT_EQ(
      ErrorOf(Nrrd(
          kRaw8Header + "space directions: (0.3,0,0) (0,0.3,0) (0,0,0.31)\n",
          Ramp8())),
      "scan.nrrd: space directions: voxels must be isotropic within 1 %, got "
      "0.3 0.3 0.31 mm");
  EXPECT_EQ(ErrorOf(Nrrd(kRaw8Header + "spacings: 0.3 nan 0.3\n", Ramp8())),
            "scan.nrrd: spacings: expected 3 positive finite numbers, got "
            "'0.3 nan 0.3'");
  EXPECT_EQ(
      ErrorOf(Nrrd(
          kRaw8Header + "space directions: (0.3,0,0) (0.3,0.3,0) (0,0,0.3)\n",
          Ramp8())),
      "scan.nrrd: space directions: axes must be orthogonal, got "
      "'(0.3,0,0) (0.3,0.3,0) (0,0,0.3)'");
  EXPECT_EQ(
      ErrorOf(Nrrd(kRaw8Header + "space directions: none (0,0.3,0) (0,0,0.3)\n",
                   Ramp8())),
      "scan.nrrd: space directions: expected 3 finite non-zero vectors like "
      "(0.3,0,0), got 'none (0,0.3,0) (0,0,0.3)'");
}

TEST(Nrrd, DetachedDataFileIsRefused) {
  EXPECT_EQ(ErrorOf("NRRD0004\n" + kRaw8Header + "data file: scan.raw\n"),
            "scan.nrrd: data file: detached data files are not supported");
}

TEST(Nrrd, OtherMalformedHeadersAreRefusedWithTheirField) {
  EXPECT_EQ(ErrorOf(Nrrd("type: uchar\ndimension: 3\nsizes: 4 3 2\n"
                         "encoding: bzip2\n",
                         Ramp8())),
            "scan.nrrd: encoding: unsupported encoding 'bzip2' (supported: "
            "raw, gzip)");
  EXPECT_EQ(ErrorOf(Nrrd("type: ushort\ndimension: 3\nsizes: 4 3 2\n"
                         "encoding: raw\n",
                         Ramp8() + Ramp8())),
            "scan.nrrd: missing required field 'endian' (needed for 16-bit "
            "data)");
  EXPECT_EQ(ErrorOf(Nrrd(kRaw8Header + "endian: middle\n", Ramp8())),
            "scan.nrrd: endian: expected 'little' or 'big', got 'middle'");
  EXPECT_EQ(ErrorOf(Nrrd(kRaw8Header + "sizes: 4 3 2\n", Ramp8())),
            "scan.nrrd: line 6: duplicate field 'sizes'");
  EXPECT_EQ(ErrorOf(Nrrd(kRaw8Header + "colour: blue\n", Ramp8())),
            "scan.nrrd: line 6: unknown field 'colour'");
  EXPECT_EQ(ErrorOf(Nrrd(kRaw8Header + "spacings 0.3\n", Ramp8())),
            "scan.nrrd: line 6: expected 'field: value', got 'spacings 0.3'");
  EXPECT_EQ(ErrorOf("NRRD0004\n" + kRaw8Header),
            "scan.nrrd: header does not end with a blank line before the data");
  EXPECT_EQ(ErrorOf(Nrrd(kRaw8Header + "space units: \"cm\" \"cm\" \"cm\"\n",
                         Ramp8())),
            "scan.nrrd: space units: only \"mm\" is supported, got '\"cm\" "
            "\"cm\" \"cm\"'");
  EXPECT_EQ(ErrorOf(Nrrd(kRaw8Header + "spacings: 0.3 0.3 0.3\n"
                                       "space directions: (0.3,0,0) (0,0.3,0) "
                                       "(0,0,0.3)\n",
                         Ramp8())),
            "scan.nrrd: spacings and space directions must not both be given");
  // Control bytes from the file are escaped so the message stays one line.
  EXPECT_EQ(ErrorOf(Nrrd("type: uchar\x01\r\x7f\ndimension: 3\n", "")),
            "scan.nrrd: type: unsupported type 'uchar\\x01\\x0d\\x7f' "
            "(supported: 8- and 16-bit integers)");
}

TEST(Nrrd, InvalidIntensityMappingIsRefused) {
  EXPECT_EQ(ErrorOf(Nrrd(kRaw8Header, Ramp8()), Linear(5, 5)),
            "scan.nrrd: intensity mapping: linear needs finite low < high, got "
            "low 5, high 5");
  EXPECT_EQ(ErrorOf(Nrrd(kRaw8Header, Ramp8()), Threshold(std::nan(""))),
            "scan.nrrd: intensity mapping: threshold must be finite, got nan");
}

TEST(Nrrd, LoadNrrdReadsAFileFromDisk) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() /
      ("burrlab_nrrd_test_" + std::to_string(std::random_device{}()));
  std::filesystem::create_directories(dir);
  const std::filesystem::path path = dir / "bone.nrrd";
  {
    std::ofstream out(path, std::ios::binary);
    out << Nrrd(kRaw8Header + "spacings: 0.2 0.2 0.2\n", Ramp8());
  }
  Result<Volume> volume = LoadNrrd(path.string(), Linear(0, 255));
  ASSERT_TRUE(volume.ok()) << volume.error().message;
  EXPECT_EQ(volume->voxel_mm(), 0.2);
  EXPECT_EQ(volume->At(3, 2, 1), 24);

  const std::string missing = (dir / "missing.nrrd").string();
  Result<Volume> none = LoadNrrd(missing, IntensityMapping{});
  ASSERT_FALSE(none.ok());
  EXPECT_EQ(none.error().message,
            missing + ": cannot open: No such file or directory");

  Result<Volume> directory = LoadNrrd(dir.string(), IntensityMapping{});
  ASSERT_FALSE(directory.ok());
  EXPECT_EQ(directory.error().message,
            dir.string() + ": cannot read: Is a directory");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace burrlab::sim
