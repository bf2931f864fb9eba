// NRRD reader (http://teem.sourceforge.net/nrrd/format.html): magic line
// NRRD0001..NRRD0005, "field: value" lines, "key:=value" lines and '#'
// comments (both ignored), a blank line, then the data. Only what a CT volume
// of bone needs is accepted: 3 axes, 8- or 16-bit integers, raw or gzip data in
// the same file, isotropic voxels. Everything else is refused with a one-line
// message naming the field.
//
// Hostile input: the header is scanned once, numbers are parsed with bounds,
// and the voxel count is checked against kMaxVolumeVoxels and against the bytes
// actually present (raw) or the most a gzip stream of that size can inflate to
// (deflate cannot exceed ~1032:1) before anything is allocated.
#include "burrlab/sim/nrrd.h"

#include <fmt/format.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace burrlab::sim {
namespace {

// Upper bound of the deflate expansion ratio, with a margin.
constexpr std::size_t kMaxInflateRatio = 1100;
// Largest file LoadNrrd reads: the largest 16-bit volume plus a header.
constexpr std::size_t kMaxFileBytes = 2 * kMaxVolumeVoxels + (1u << 20);
// Longest excerpt of the file quoted in an error message.
constexpr std::size_t kMaxQuote = 48;

enum class SampleType { kUint8, kInt8, kUint16, kInt16 };
enum class Encoding { kRaw, kGzip };

// Header fields burrlab reads; the others NRRD defines are accepted and
// ignored.
enum class Field {
  kDimension,
  kType,
  kSizes,
  kEncoding,
  kEndian,
  kSpacings,
  kSpaceDirections,
  kSpaceUnits,
  kLineSkip,
  kByteSkip,
  kDataFile,
  kIgnored,
};

struct FieldName {
  std::string_view name;
  Field field;
};

// Field identifiers of NRRD0005 (and their older spellings without spaces).
constexpr std::array<FieldName, 40> kFieldNames = {{
    {"dimension", Field::kDimension},
    {"type", Field::kType},
    {"sizes", Field::kSizes},
    {"encoding", Field::kEncoding},
    {"endian", Field::kEndian},
    {"spacings", Field::kSpacings},
    {"space directions", Field::kSpaceDirections},
    {"space units", Field::kSpaceUnits},
    {"line skip", Field::kLineSkip},
    {"lineskip", Field::kLineSkip},
    {"byte skip", Field::kByteSkip},
    {"byteskip", Field::kByteSkip},
    {"data file", Field::kDataFile},
    {"datafile", Field::kDataFile},
    {"content", Field::kIgnored},
    {"block size", Field::kIgnored},
    {"blocksize", Field::kIgnored},
    {"kinds", Field::kIgnored},
    {"centers", Field::kIgnored},
    {"centerings", Field::kIgnored},
    {"labels", Field::kIgnored},
    {"units", Field::kIgnored},
    {"thicknesses", Field::kIgnored},
    {"axis mins", Field::kIgnored},
    {"axismins", Field::kIgnored},
    {"axis maxs", Field::kIgnored},
    {"axismaxs", Field::kIgnored},
    {"min", Field::kIgnored},
    {"max", Field::kIgnored},
    {"old min", Field::kIgnored},
    {"oldmin", Field::kIgnored},
    {"old max", Field::kIgnored},
    {"oldmax", Field::kIgnored},
    {"sample units", Field::kIgnored},
    {"sampleunits", Field::kIgnored},
    {"number", Field::kIgnored},
    {"space", Field::kIgnored},
    {"space dimension", Field::kIgnored},
    {"space origin", Field::kIgnored},
    {"measurement frame", Field::kIgnored},
}};

constexpr std::size_t kFieldCount = static_cast<std::size_t>(Field::kIgnored);

std::string Lower(std::string_view text) {
  std::string out(text);
  for (char& c : out) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return out;
}

bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\r'; }

std::string_view Trim(std::string_view text) {
  while (!text.empty() && IsSpace(text.front())) text.remove_prefix(1);
  while (!text.empty() && IsSpace(text.back())) text.remove_suffix(1);
  return text;
}

std::vector<std::string_view> SplitWhitespace(std::string_view text) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && IsSpace(text[i])) ++i;
    const std::size_t start = i;
    while (i < text.size() && !IsSpace(text[i])) ++i;
    if (i > start) words.push_back(text.substr(start, i - start));
  }
  return words;
}

// `text` between single quotes, printable ASCII only (other bytes as \xNN),
// shortened so an error message stays one short line.
std::string Quote(std::string_view text) {
  std::string out = "'";
  const bool shorten = text.size() > kMaxQuote;
  if (shorten) text = text.substr(0, kMaxQuote);
  for (char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte >= 0x7f) {
      out += fmt::format("\\x{:02x}", byte);
    } else {
      out += c;
    }
  }
  out += shorten ? "...'" : "'";
  return out;
}

std::optional<std::int64_t> ParseInt(std::string_view text) {
  std::int64_t value = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (ec != std::errc() || ptr != end) return std::nullopt;
  return value;
}

std::optional<double> ParseDouble(std::string_view text) {
  double value = 0.0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (ec != std::errc() || ptr != end) return std::nullopt;
  return value;
}

Error DetachedData() {
  return Error{"data file: detached data files are not supported"};
}

// One header field as written.
struct RawField {
  std::string_view value;
  bool present = false;
};

// The header split into fields, and where the data starts.
struct Header {
  std::array<RawField, kFieldCount> fields;
  std::size_t data_offset = 0;

  const RawField& Get(Field f) const {
    return fields[static_cast<std::size_t>(f)];
  }
};

// What the header says about the data.
struct Layout {
  SampleType type = SampleType::kUint8;
  Encoding encoding = Encoding::kRaw;
  bool big_endian = false;
  std::array<int, 3> sizes = {0, 0, 0};
  double voxel_mm = 0.3;
  std::int64_t line_skip = 0;
  std::int64_t byte_skip = 0;

  std::size_t Voxels() const {
    return static_cast<std::size_t>(sizes[0]) *
           static_cast<std::size_t>(sizes[1]) *
           static_cast<std::size_t>(sizes[2]);
  }
  std::size_t BytesPerSample() const {
    return type == SampleType::kUint16 || type == SampleType::kInt16 ? 2 : 1;
  }
};

// Returns the next line (without '\n' and a trailing '\r') and advances *pos;
// *terminated says whether the line ended with '\n'.
std::string_view NextLine(std::string_view bytes, std::size_t* pos,
                          bool* terminated) {
  const std::size_t start = *pos;
  const std::size_t newline = bytes.find('\n', start);
  *terminated = newline != std::string_view::npos;
  const std::size_t end = *terminated ? newline : bytes.size();
  *pos = *terminated ? newline + 1 : bytes.size();
  std::string_view line = bytes.substr(start, end - start);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  return line;
}

// A header that runs to the end of the file: a detached header (refused as
// such) or a file cut short.
Error EndOfHeaderMissing(const Header& header) {
  if (header.Get(Field::kDataFile).present) return DetachedData();
  return Error{"header does not end with a blank line before the data"};
}

Result<Header> ScanHeader(std::string_view bytes) {
  Header header;
  std::size_t pos = 0;
  bool terminated = false;
  const std::string_view magic = NextLine(bytes, &pos, &terminated);
  if (magic.size() != 8 || magic.substr(0, 7) != "NRRD000" || magic[7] < '1' ||
      magic[7] > '5') {
    return Error{fmt::format(
        "not an NRRD file: first line is {}, expected NRRD0001 to NRRD0005",
        Quote(magic))};
  }
  for (int line_number = 2;; ++line_number) {
    if (!terminated) return EndOfHeaderMissing(header);
    const std::string_view line = NextLine(bytes, &pos, &terminated);
    if (line.empty()) {
      if (!terminated) return EndOfHeaderMissing(header);
      header.data_offset = pos;
      return header;
    }
    if (line.front() == '#') continue;
    // "field: value", or "key:=value" (keys may hold ':'; not burrlab's
    // concern).
    const std::size_t colon = line.find(": ");
    const std::size_t key_value = line.find(":=");
    if (key_value < colon) continue;
    if (colon == std::string_view::npos) {
      return Error{fmt::format("line {}: expected 'field: value', got {}",
                               line_number, Quote(line))};
    }
    const std::string name = Lower(Trim(line.substr(0, colon)));
    const auto known =
        std::find_if(kFieldNames.begin(), kFieldNames.end(),
                     [&name](const FieldName& f) { return f.name == name; });
    if (known == kFieldNames.end()) {
      return Error{
          fmt::format("line {}: unknown field {}", line_number, Quote(name))};
    }
    if (known->field == Field::kIgnored) continue;
    RawField& field = header.fields[static_cast<std::size_t>(known->field)];
    if (field.present) {
      return Error{
          fmt::format("line {}: duplicate field {}", line_number, Quote(name))};
    }
    field.present = true;
    field.value = Trim(line.substr(colon + 2));
  }
}

Error Missing(std::string_view field) {
  return Error{fmt::format("missing required field '{}'", field)};
}

std::optional<SampleType> ParseType(std::string_view value) {
  const std::string type = Lower(value);
  for (std::string_view name : {"uchar", "unsigned char", "uint8", "uint8_t"}) {
    if (type == name) return SampleType::kUint8;
  }
  for (std::string_view name : {"signed char", "int8", "int8_t"}) {
    if (type == name) return SampleType::kInt8;
  }
  for (std::string_view name : {"short", "short int", "signed short",
                                "signed short int", "int16", "int16_t"}) {
    if (type == name) return SampleType::kInt16;
  }
  for (std::string_view name : {"ushort", "unsigned short",
                                "unsigned short int", "uint16", "uint16_t"}) {
    if (type == name) return SampleType::kUint16;
  }
  return std::nullopt;
}

// Voxel size from three axis lengths that must agree within 1 %: the median.
Result<double> IsotropicVoxel(std::string_view field,
                              std::array<double, 3> lengths) {
  const std::array<double, 3> given = lengths;
  std::sort(lengths.begin(), lengths.end());
  if (lengths[2] > 1.01 * lengths[0]) {
    return Error{
        fmt::format("{}: voxels must be isotropic within 1 %, got {} {} {} mm",
                    field, given[0], given[1], given[2])};
  }
  return lengths[1];
}

Result<double> ParseSpacings(std::string_view value) {
  const std::vector<std::string_view> words = SplitWhitespace(value);
  std::array<double, 3> spacing{};
  bool valid = words.size() == 3;
  for (std::size_t a = 0; valid && a < 3; ++a) {
    const std::optional<double> s = ParseDouble(words[a]);
    valid = s && std::isfinite(*s) && *s > 0.0;
    if (valid) spacing[a] = *s;
  }
  if (!valid) {
    return Error{fmt::format(
        "spacings: expected 3 positive finite numbers, got {}", Quote(value))};
  }
  return IsotropicVoxel("spacings", spacing);
}

// "(a,b,c) (d,e,f) (g,h,i)": three orthogonal axis vectors of isotropic length.
Result<double> ParseSpaceDirections(std::string_view value) {
  const Error malformed{fmt::format(
      "space directions: expected 3 finite non-zero vectors like (0.3,0,0), "
      "got {}",
      Quote(value))};
  std::vector<std::vector<double>> axes;
  std::string_view rest = Trim(value);
  while (!rest.empty()) {
    if (rest.front() != '(') return malformed;
    const std::size_t close = rest.find(')');
    if (close == std::string_view::npos) return malformed;
    std::string_view inside = rest.substr(1, close - 1);
    std::vector<double> vector;
    while (true) {
      const std::size_t comma = inside.find(',');
      const std::optional<double> c =
          ParseDouble(Trim(inside.substr(0, comma)));
      if (!c || !std::isfinite(*c) || vector.size() >= 16) return malformed;
      vector.push_back(*c);
      if (comma == std::string_view::npos) break;
      inside.remove_prefix(comma + 1);
    }
    if (!axes.empty() && vector.size() != axes.front().size()) return malformed;
    axes.push_back(std::move(vector));
    if (axes.size() > 3) return malformed;
    rest = Trim(rest.substr(close + 1));
  }
  if (axes.size() != 3) return malformed;
  std::array<double, 3> lengths{};
  for (std::size_t a = 0; a < 3; ++a) {
    // Scaled by the largest component so the length cannot overflow.
    double largest = 0.0;
    for (double c : axes[a]) largest = std::max(largest, std::abs(c));
    if (largest == 0.0) return malformed;
    double sum = 0.0;
    for (double c : axes[a]) sum += (c / largest) * (c / largest);
    lengths[a] = largest * std::sqrt(sum);
    if (!std::isfinite(lengths[a])) return malformed;
  }
  for (std::size_t a = 0; a < 3; ++a) {
    for (std::size_t b = a + 1; b < 3; ++b) {
      double cosine = 0.0;
      for (std::size_t c = 0; c < axes[a].size(); ++c) {
        cosine += (axes[a][c] / lengths[a]) * (axes[b][c] / lengths[b]);
      }
      if (std::abs(cosine) > 0.01) {
        return Error{fmt::format(
            "space directions: axes must be orthogonal, got {}", Quote(value))};
      }
    }
  }
  return IsotropicVoxel("space directions", lengths);
}

// "mm" for every axis: the only length unit burrlab works in.
Status CheckSpaceUnits(std::string_view value) {
  const Error wrong{fmt::format("space units: only \"mm\" is supported, got {}",
                                Quote(value))};
  std::string_view rest = Trim(value);
  if (rest.empty()) return wrong;
  while (!rest.empty()) {
    if (rest.front() != '"') return wrong;
    const std::size_t close = rest.find('"', 1);
    if (close == std::string_view::npos) return wrong;
    if (Lower(rest.substr(1, close - 1)) != "mm") return wrong;
    rest = Trim(rest.substr(close + 1));
  }
  return {};
}

Result<Layout> InterpretHeader(const Header& header) {
  Layout layout;
  if (header.Get(Field::kDataFile).present) return DetachedData();

  const RawField& dimension = header.Get(Field::kDimension);
  if (!dimension.present) return Missing("dimension");
  if (dimension.value != "3") {
    return Error{
        fmt::format("dimension: expected 3, got {}", Quote(dimension.value))};
  }

  const RawField& type = header.Get(Field::kType);
  if (!type.present) return Missing("type");
  const std::optional<SampleType> sample = ParseType(type.value);
  if (!sample) {
    return Error{fmt::format(
        "type: unsupported type {} (supported: 8- and 16-bit integers)",
        Quote(type.value))};
  }
  layout.type = *sample;

  const RawField& sizes = header.Get(Field::kSizes);
  if (!sizes.present) return Missing("sizes");
  const std::vector<std::string_view> words = SplitWhitespace(sizes.value);
  std::array<std::int64_t, 3> extent{};
  bool valid = words.size() == 3;
  for (std::size_t a = 0; valid && a < 3; ++a) {
    const std::optional<std::int64_t> n = ParseInt(words[a]);
    valid = n && *n > 0;
    if (valid) extent[a] = *n;
  }
  if (!valid) {
    return Error{fmt::format("sizes: expected 3 positive integers, got {}",
                             Quote(sizes.value))};
  }
  for (std::size_t a = 0; a < 3; ++a) {
    if (extent[a] > kMaxVolumeExtent) {
      return Error{
          fmt::format("sizes: {} {} {} exceeds the limit of {} voxels per axis",
                      extent[0], extent[1], extent[2], kMaxVolumeExtent)};
    }
    layout.sizes[a] = static_cast<int>(extent[a]);
  }
  if (layout.Voxels() > kMaxVolumeVoxels) {
    return Error{fmt::format(
        "sizes: {} {} {} is {} voxels, above the limit of {}", extent[0],
        extent[1], extent[2], layout.Voxels(), kMaxVolumeVoxels)};
  }

  const RawField& encoding = header.Get(Field::kEncoding);
  if (!encoding.present) return Missing("encoding");
  const std::string encoding_name = Lower(encoding.value);
  if (encoding_name == "raw") {
    layout.encoding = Encoding::kRaw;
  } else if (encoding_name == "gzip" || encoding_name == "gz") {
    layout.encoding = Encoding::kGzip;
  } else {
    return Error{
        fmt::format("encoding: unsupported encoding {} (supported: raw, gzip)",
                    Quote(encoding.value))};
  }

  const RawField& endian = header.Get(Field::kEndian);
  if (endian.present) {
    const std::string order = Lower(endian.value);
    if (order != "little" && order != "big") {
      return Error{fmt::format("endian: expected 'little' or 'big', got {}",
                               Quote(endian.value))};
    }
    layout.big_endian = order == "big";
  } else if (layout.BytesPerSample() > 1) {
    return Error{"missing required field 'endian' (needed for 16-bit data)"};
  }

  const RawField& spacings = header.Get(Field::kSpacings);
  const RawField& directions = header.Get(Field::kSpaceDirections);
  if (spacings.present && directions.present) {
    return Error{"spacings and space directions must not both be given"};
  }
  if (spacings.present || directions.present) {
    Result<double> voxel = spacings.present
                               ? ParseSpacings(spacings.value)
                               : ParseSpaceDirections(directions.value);
    if (!voxel.ok()) return voxel.error();
    layout.voxel_mm = *voxel;
  }
  const RawField& units = header.Get(Field::kSpaceUnits);
  if (units.present) {
    const Status status = CheckSpaceUnits(units.value);
    if (!status.ok()) return status.error();
  }

  const RawField& line_skip = header.Get(Field::kLineSkip);
  if (line_skip.present) {
    const std::optional<std::int64_t> n = ParseInt(line_skip.value);
    if (!n || *n < 0) {
      return Error{fmt::format("line skip: expected an integer >= 0, got {}",
                               Quote(line_skip.value))};
    }
    layout.line_skip = *n;
  }
  const RawField& byte_skip = header.Get(Field::kByteSkip);
  if (byte_skip.present) {
    const std::optional<std::int64_t> n = ParseInt(byte_skip.value);
    if (!n || *n < -1) {
      return Error{fmt::format("byte skip: expected an integer >= -1, got {}",
                               Quote(byte_skip.value))};
    }
    if (*n != 0 && layout.encoding == Encoding::kGzip) {
      return Error{fmt::format(
          "byte skip: only 0 is supported with gzip encoding, got {}", *n)};
    }
    layout.byte_skip = *n;
  }
  return layout;
}

// Inflates a gzip stream (one or more members) into exactly out.size() bytes.
Status Inflate(std::string_view in, std::vector<std::uint8_t>& out) {
  const std::size_t expected = out.size();
  z_stream stream{};
  if (inflateInit2(&stream, 16 + MAX_WBITS) != Z_OK) {
    return Error{"gzip data: cannot initialise zlib"};
  }
  struct Ender {
    z_stream* s;
    ~Ender() { inflateEnd(s); }
  } ender{&stream};

  constexpr std::size_t kChunk = std::size_t{1} << 30;  // fits zlib's uInt
  std::size_t in_pos = 0;
  std::size_t out_pos = 0;
  Bytef spill = 0;
  while (true) {
    if (stream.avail_in == 0 && in_pos < in.size()) {
      const std::size_t n = std::min(kChunk, in.size() - in_pos);
      // zlib's next_in is not const in older headers; it is never written.
      stream.next_in =
          reinterpret_cast<Bytef*>(const_cast<char*>(in.data() + in_pos));
      stream.avail_in = static_cast<uInt>(n);
      in_pos += n;
    }
    const bool full = out_pos == expected;
    if (full) {
      stream.next_out = &spill;
      stream.avail_out = 1;
    } else {
      stream.next_out = out.data() + out_pos;
      stream.avail_out =
          static_cast<uInt>(std::min(kChunk, expected - out_pos));
    }
    const uInt room = stream.avail_out;
    const int rc = inflate(&stream, Z_NO_FLUSH);
    const std::size_t produced = room - stream.avail_out;
    if (full && produced > 0) {
      return Error{fmt::format(
          "gzip data: decompresses to more than the expected {} bytes",
          expected)};
    }
    out_pos += produced;
    const std::size_t unread = stream.avail_in + (in.size() - in_pos);
    switch (rc) {
      case Z_OK:
        continue;
      case Z_STREAM_END:
        if (unread == 0) {
          if (out_pos < expected) {
            return Error{
                fmt::format("gzip data: decompressed to {} bytes, expected {}",
                            out_pos, expected)};
          }
          return {};
        }
        if (out_pos == expected) {
          return Error{fmt::format(
              "gzip data: {} bytes of trailing data after the compressed "
              "stream",
              unread)};
        }
        // Another gzip member follows (concatenated streams are valid gzip).
        if (inflateReset(&stream) != Z_OK) {
          return Error{"gzip data: cannot reset zlib"};
        }
        continue;
      case Z_BUF_ERROR:
        if (unread == 0) {
          return Error{fmt::format(
              "gzip data: compressed stream is truncated (decompressed {} of "
              "{} bytes)",
              out_pos, expected)};
        }
        return Error{"gzip data: corrupt compressed stream (no progress)"};
      case Z_MEM_ERROR:
        return Error{"gzip data: out of memory while decompressing"};
      default:
        return Error{fmt::format("gzip data: corrupt compressed stream ({})",
                                 stream.msg != nullptr
                                     ? Quote(stream.msg)
                                     : std::string("zlib error"))};
    }
  }
}

// Occupancy of every possible sample value (256 or 65536 entries, indexed by
// the raw bits in host order).
std::vector<std::uint8_t> BuildLookup(SampleType type,
                                      const IntensityMapping& mapping) {
  const std::size_t entries =
      type == SampleType::kUint8 || type == SampleType::kInt8 ? 256 : 65536;
  std::vector<std::uint8_t> lookup(entries);
  for (std::size_t bits = 0; bits < entries; ++bits) {
    double intensity = static_cast<double>(bits);
    if (type == SampleType::kInt8 && bits >= 128) intensity -= 256.0;
    if (type == SampleType::kInt16 && bits >= 32768) intensity -= 65536.0;
    std::uint8_t occupancy = 0;
    if (mapping.kind == IntensityMapping::Kind::kThreshold) {
      occupancy = intensity >= mapping.threshold ? kSolidOccupancy : 0;
    } else if (intensity >= mapping.high) {
      occupancy = kSolidOccupancy;
    } else if (intensity > mapping.low) {
      const double scaled = kSolidOccupancy * (intensity - mapping.low) /
                            (mapping.high - mapping.low);
      occupancy = static_cast<std::uint8_t>(
          std::lround(std::clamp(scaled, 0.0, double{kSolidOccupancy})));
    }
    lookup[bits] = occupancy;
  }
  return lookup;
}

Status CheckMapping(const IntensityMapping& mapping) {
  if (mapping.kind == IntensityMapping::Kind::kThreshold) {
    if (!std::isfinite(mapping.threshold)) {
      return Error{
          fmt::format("intensity mapping: threshold must be finite, got {}",
                      mapping.threshold)};
    }
    return {};
  }
  if (mapping.kind != IntensityMapping::Kind::kLinear) {
    return Error{"intensity mapping: unknown kind"};
  }
  if (!std::isfinite(mapping.low) || !std::isfinite(mapping.high) ||
      !(mapping.low < mapping.high)) {
    return Error{fmt::format(
        "intensity mapping: linear needs finite low < high, got low {}, high "
        "{}",
        mapping.low, mapping.high)};
  }
  return {};
}

Result<Volume> Parse(std::string_view bytes, const IntensityMapping& mapping) {
  const Status mapping_ok = CheckMapping(mapping);
  if (!mapping_ok.ok()) return mapping_ok.error();
  Result<Header> header = ScanHeader(bytes);
  if (!header.ok()) return header.error();
  Result<Layout> layout_or = InterpretHeader(*header);
  if (!layout_or.ok()) return layout_or.error();
  const Layout& layout = *layout_or;

  std::string_view data = bytes.substr(header->data_offset);
  for (std::int64_t n = 0; n < layout.line_skip; ++n) {
    const std::size_t newline = data.find('\n');
    if (newline == std::string_view::npos) {
      return Error{
          fmt::format("line skip: {} lines skipped past the end of the file",
                      layout.line_skip)};
    }
    data.remove_prefix(newline + 1);
  }

  const std::size_t expected = layout.Voxels() * layout.BytesPerSample();
  std::vector<std::uint8_t> inflated;
  if (layout.encoding == Encoding::kRaw) {
    if (layout.byte_skip == -1) {
      if (data.size() < expected) {
        return Error{fmt::format("raw data: expected {} bytes, got {}",
                                 expected, data.size())};
      }
      data = data.substr(data.size() - expected);
    } else {
      if (static_cast<std::uint64_t>(layout.byte_skip) > data.size()) {
        return Error{fmt::format("byte skip: {} is past the end of the file",
                                 layout.byte_skip)};
      }
      data.remove_prefix(static_cast<std::size_t>(layout.byte_skip));
      if (data.size() != expected) {
        return Error{fmt::format("raw data: expected {} bytes, got {}",
                                 expected, data.size())};
      }
    }
  } else {
    if (data.size() < expected / kMaxInflateRatio) {
      return Error{fmt::format(
          "gzip data: compressed stream is truncated ({} compressed bytes "
          "cannot hold {} bytes)",
          data.size(), expected)};
    }
    inflated.resize(expected);
    const Status status = Inflate(data, inflated);
    if (!status.ok()) return status.error();
    data = std::string_view(reinterpret_cast<const char*>(inflated.data()),
                            inflated.size());
  }

  Result<Volume> volume = Volume::Create(layout.sizes[0], layout.sizes[1],
                                         layout.sizes[2], layout.voxel_mm);
  if (!volume.ok()) return volume;
  const std::vector<std::uint8_t> lookup = BuildLookup(layout.type, mapping);
  std::uint8_t* occupancy = volume->occupancy();
  const auto* in = reinterpret_cast<const std::uint8_t*>(data.data());
  const std::size_t voxels = layout.Voxels();
  if (layout.BytesPerSample() == 1) {
    for (std::size_t v = 0; v < voxels; ++v) occupancy[v] = lookup[in[v]];
  } else {
    const std::size_t hi = layout.big_endian ? 0 : 1;
    const std::size_t lo = 1 - hi;
    for (std::size_t v = 0; v < voxels; ++v) {
      const std::size_t bits =
          (std::size_t{in[2 * v + hi]} << 8) | std::size_t{in[2 * v + lo]};
      occupancy[v] = lookup[bits];
    }
  }
  return volume;
}

}  // namespace

Result<Volume> ParseNrrd(std::string_view name, std::string_view bytes,
                         const IntensityMapping& mapping) {
  Result<Volume> volume = Parse(bytes, mapping);
  if (!volume.ok()) {
    return Error{fmt::format("{}: {}", name, volume.error().message)};
  }
  return volume;
}

Result<Volume> LoadNrrd(const std::string& path,
                        const IntensityMapping& mapping) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) {
    return Error{fmt::format("{}: cannot open: {}", path,
                             std::generic_category().message(errno))};
  }
  struct Closer {
    std::FILE* f;
    ~Closer() { std::fclose(f); }
  } closer{file};
  std::string bytes;
  std::array<char, 1 << 16> buffer;
  while (true) {
    const std::size_t n = std::fread(buffer.data(), 1, buffer.size(), file);
    if (n > 0) {
      if (bytes.size() + n > kMaxFileBytes) {
        return Error{fmt::format("{}: file is larger than {} bytes", path,
                                 kMaxFileBytes)};
      }
      bytes.append(buffer.data(), n);
    }
    if (n < buffer.size()) break;
  }
  if (std::ferror(file)) {
    return Error{fmt::format("{}: cannot read: {}", path,
                             std::generic_category().message(errno))};
  }
  return ParseNrrd(path, bytes, mapping);
}

}  // namespace burrlab::sim
