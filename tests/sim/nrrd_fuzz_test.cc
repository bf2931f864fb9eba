// ParseNrrd on hostile input: thousands of random byte strings, random headers
// and mutations (bit flips, truncations, insertions, header line swaps and
// duplications) of valid files, from a fixed seed. Every call must return, and
// every failure must carry a non-empty one-line message naming the file.
#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "burrlab/sim/nrrd.h"
#include "gzip_for_tests.h"

namespace burrlab::sim {
namespace {

using testing::Gzip;

// Valid 8 x 8 x 8 files covering each type, encoding, byte order and way of
// giving the voxel size.
std::vector<std::string> ValidFiles(std::mt19937& rng) {
  std::string bytes8(512, '\0');
  std::string bytes16(1024, '\0');
  for (char& c : bytes8) c = static_cast<char>(rng() & 0x3f);
  for (char& c : bytes16) c = static_cast<char>(rng() & 0x0f);
  const std::string sizes = "dimension: 3\nsizes: 8 8 8\n";
  return {
      "NRRD0004\n# comment\ntype: uchar\n" + sizes +
          "encoding: raw\nspacings: 0.3 0.3 0.3\n\n" + bytes8,
      "NRRD0005\ntype: short\n" + sizes +
          "encoding: raw\nendian: little\nkey:=value\n"
          "space directions: (0.2,0,0) (0,0.2,0) (0,0,0.2)\n\n" +
          bytes16,
      "NRRD0004\ntype: uint16\n" + sizes +
          "encoding: gzip\nendian: big\nspace units: \"mm\" \"mm\" \"mm\"\n\n" +
          Gzip(bytes16),
      "NRRD0001\r\ntype: int8\r\ndimension: 3\r\nsizes: 8 8 8\r\n"
      "encoding: gz\r\nline skip: 1\r\n\r\nskipped\n" +
          Gzip(bytes8),
      "NRRD0003\ntype: unsigned char\n" + sizes +
          "encoding: raw\nbyte skip: -1\n\npadding" + bytes8,
  };
}

// A field of NRRD's vocabulary with plausible and implausible values.
struct FuzzField {
  std::string_view name;
  std::array<std::string_view, 6> values;
};

// Header-like text: the fields in random order (the required ones present
// with probability 7/8, the others 2/3) with values that are mostly valid, then
// data of a length that often fits the sizes, so many headers reach the data.
std::string RandomHeader(std::mt19937& rng) {
  static const std::array<FuzzField, 12> kFields = {{
      {"type", {"uchar", "short", "ushort", "int8", "float", "uint8"}},
      {"dimension", {"3", "3", "3", "2", "4", "-3"}},
      {"sizes",
       {"2 2 2", "4 3 2", "1 1 1", "2048 2048 2048", "0 1 2",
        "99999999999999999999 1 1"}},
      {"encoding", {"raw", "raw", "gzip", "gz", "ascii", "bzip2"}},
      {"endian", {"little", "big", "little", "big", "middle", ""}},
      {"spacings",
       {"0.3 0.3 0.3", "1 1 1", "nan inf 0", "1e308 1e308 1e308", "0.3 0.6 0.3",
        "-1 -1 -1"}},
      {"space directions",
       {"(1,0,0) (0,1,0) (0,0,1)", "(1,0) (0,1) (1,1)",
        "(0,0,0) (0,1,0) (0,0,1)", "none (0,1,0) (0,0,1)",
        "(1e308,1e308,0) (0,0,1e308) (1,-1,0)",
        "(1,0,0) (0,1,0) (0,0,1) (1,1,1)"}},
      {"space units",
       {"\"mm\" \"mm\" \"mm\"", "\"cm\"", "mm", "\"mm", "", "\"\""}},
      {"line skip", {"0", "1", "3", "-1", "x", "100000000000"}},
      {"byte skip", {"0", "-1", "1", "2", "-2", "100000000000"}},
      {"data file", {"LIST", "scan.raw", "", "%d.raw 1 2 1", "x", "y"}},
      {"content", {"bone", "", ":", ": :=", "\t", "#"}},
  }};
  std::string text = "NRRD000" + std::to_string(rng() % 7) + "\n";
  std::array<std::size_t, kFields.size()> order{};
  for (std::size_t f = 0; f < order.size(); ++f) order[f] = f;
  std::shuffle(order.begin(), order.end(), rng);
  for (std::size_t f : order) {
    // Required fields are more often present than the optional ones.
    if (rng() % (f < 5 ? 8 : 3) != 0) continue;
    const FuzzField& field = kFields[f];
    text += field.name;
    text += rng() % 16 == 0 ? ":=" : ": ";
    text += field.values[rng() % field.values.size()];
    text += '\n';
  }
  if (rng() % 8 != 0) text += '\n';
  static constexpr std::array<std::size_t, 6> kLengths = {8, 16, 24, 48, 0, 5};
  std::string data(kLengths[rng() % kLengths.size()], '\0');
  for (char& c : data) c = static_cast<char>(rng());
  return text + (rng() % 3 == 0 ? Gzip(data) : data);
}

std::string RandomBytes(std::mt19937& rng) {
  std::string bytes(rng() % 300, '\0');
  for (char& c : bytes) c = static_cast<char>(rng());
  return bytes;
}

std::string Mutate(std::string file, std::mt19937& rng) {
  const std::size_t edits = 1 + rng() % 4;
  for (std::size_t e = 0; e < edits && !file.empty(); ++e) {
    const std::size_t op = rng() % 6;
    switch (op) {
      case 0: {  // bit flips, mostly in the header
        const std::size_t at =
            rng() % 2 ? rng() % std::min<std::size_t>(file.size(), 160)
                      : rng() % file.size();
        file[at] = static_cast<char>(file[at] ^ (1 << (rng() % 8)));
        break;
      }
      case 1:  // truncation
        file.resize(rng() % file.size());
        break;
      case 2: {  // insertion of random bytes
        std::string insert(1 + rng() % 8, '\0');
        for (char& c : insert) c = static_cast<char>(rng());
        file.insert(rng() % (file.size() + 1), insert);
        break;
      }
      case 3:    // swap two header lines
      case 4: {  // or duplicate one
        std::vector<std::string> lines;
        const std::size_t end = file.find("\n\n");
        if (end == std::string::npos) break;
        std::size_t start = 0;
        while (start <= end) {
          const std::size_t nl = file.find('\n', start);
          lines.push_back(file.substr(start, nl - start + 1));
          start = nl + 1;
        }
        const std::size_t a = rng() % lines.size();
        const std::size_t b = rng() % lines.size();
        if (op == 3) {
          std::swap(lines[a], lines[b]);
        } else {
          lines.insert(lines.begin() + static_cast<std::ptrdiff_t>(a),
                       lines[b]);
        }
        std::string header;
        for (const std::string& line : lines) header += line;
        file = header + file.substr(end + 1);
        break;
      }
      default: {  // overwrite a digit to change sizes, skips or spacings
        const std::size_t digit =
            file.find_first_of("0123456789", rng() % file.size());
        if (digit != std::string::npos && digit < 200) {
          file[digit] = static_cast<char>('0' + rng() % 10);
        }
        break;
      }
    }
  }
  return file;
}

void ExpectWellBehaved(const std::string& bytes, int round) {
  IntensityMapping mapping;
  if (round % 2) {
    mapping.kind = IntensityMapping::Kind::kLinear;
    mapping.low = -100.0;
    mapping.high = 40.0;
  }
  Result<Volume> volume = ParseNrrd("fuzz.nrrd", bytes, mapping);
  if (volume.ok()) {
    ASSERT_EQ(volume->size(), static_cast<std::size_t>(volume->nx()) *
                                  static_cast<std::size_t>(volume->ny()) *
                                  static_cast<std::size_t>(volume->nz()));
    ASSERT_LE(volume->size(), bytes.size() * 1100 + 1024) << "round " << round;
    ASSERT_GT(volume->voxel_mm(), 0.0);
    return;
  }
  const std::string& message = volume.error().message;
  ASSERT_GT(message.size(), std::string("fuzz.nrrd: ").size())
      << "round " << round;
  ASSERT_EQ(message.rfind("fuzz.nrrd: ", 0), 0u) << message;
  ASSERT_EQ(message.find_first_of("\n\r"), std::string::npos)
      << "round " << round << ": " << message;
}

TEST(NrrdFuzz, ValidFilesParse) {
  std::mt19937 rng(20240611);
  for (const std::string& file : ValidFiles(rng)) {
    Result<Volume> volume = ParseNrrd("fuzz.nrrd", file, IntensityMapping{});
    ASSERT_TRUE(volume.ok()) << volume.error().message;
    EXPECT_EQ(volume->size(), 512u);
  }
}

TEST(NrrdFuzz, RandomBytesAndMutatedFilesNeverCrashAndFailInOneLine) {
  std::mt19937 rng(20240611);
  const std::vector<std::string> valid = ValidFiles(rng);
  int round = 0;
  int accepted = 0;
  for (int n = 0; n < 2000; ++n, ++round) {
    ExpectWellBehaved(RandomBytes(rng), round);
  }
  for (int n = 0; n < 8000; ++n, ++round) {
    ExpectWellBehaved(RandomHeader(rng), round);
  }
  for (int n = 0; n < 8000; ++n, ++round) {
    const std::string file = Mutate(valid[rng() % valid.size()], rng);
    ExpectWellBehaved(file, round);
    accepted += ParseNrrd("fuzz.nrrd", file, IntensityMapping{}).ok() ? 1 : 0;
  }
  // Some mutations (e.g. in the data or a comment) leave a valid file: the
  // mutations explore both sides.
  EXPECT_GT(accepted, 200);
  EXPECT_LT(accepted, 7800);
}

}  // namespace
}  // namespace burrlab::sim
