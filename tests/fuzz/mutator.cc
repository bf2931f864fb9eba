// The deterministic mutator.
#include "mutator.h"

#include <algorithm>
#include <array>
#include <cassert>

namespace burrlab::fuzz {
namespace {

// Numbers parsers must refuse or hold: extremes, signed zero, non-finite
// spellings, overflow of int, int64 and double, denormals.
constexpr std::array<std::string_view, 22> kExtremeNumbers = {
    "1e308",
    "-1e308",
    "1e309",
    "-0",
    "-0.0",
    "nan",
    "inf",
    "-inf",
    "NaN",
    "99999999999999999999",
    "1e-320",
    "0",
    "-1",
    "2147483648",
    "4294967296",
    "9223372036854775808",
    "-9223372036854775809",
    "0x7fffffff",
    "1e999",
    "+1",
    ".5",
    "5."};

// Bytes that change how lines, cells and text are read.
constexpr std::array<std::string_view, 12> kSpecialBytes = {
    "\r",
    "\n",
    "\r\n",
    "\t",
    "\xEF\xBB\xBF",
    "\x1b[31m",
    std::string_view("\0", 1),
    "\xff",
    "\xc3",
    "\xc2\x85",
    "\"",
    "\\"};

bool IsNumberChar(char c) {
  return (c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+' ||
         c == 'e' || c == 'E';
}

}  // namespace

std::vector<std::string> ParseDictionary(std::string_view text) {
  std::vector<std::string> tokens;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = text.substr(start, end - start);
    start = end + 1;
    const std::size_t open = line.find('"');
    if (line.empty() || line[0] == '#' || open == std::string_view::npos) {
      continue;
    }
    std::string token;
    for (std::size_t i = open + 1; i < line.size() && line[i] != '"'; ++i) {
      if (line[i] != '\\' || i + 1 >= line.size()) {
        token += line[i];
      } else if (line[i + 1] == 'x' && i + 3 < line.size()) {
        token += static_cast<char>(
            std::stoi(std::string(line.substr(i + 2, 2)), nullptr, 16));
        i += 3;
      } else {
        token += line[++i];
      }
    }
    tokens.push_back(std::move(token));
  }
  return tokens;
}

Mutator::Mutator(std::uint64_t seed, std::vector<std::string> corpus,
                 std::vector<std::string> dictionary, std::size_t max_len)
    : engine_(seed),
      corpus_(std::move(corpus)),
      dictionary_(std::move(dictionary)),
      max_len_(max_len) {
  assert(!corpus_.empty());
}

std::size_t Mutator::Below(std::size_t n) {
  return static_cast<std::size_t>(engine_() % n);
}

std::string Mutator::Next() {
  std::string s = corpus_[Below(corpus_.size())];
  const std::size_t mutations = 1 + Below(5);
  for (std::size_t k = 0; k < mutations; ++k) MutateOnce(&s);
  if (s.size() > max_len_) s.resize(max_len_);
  return s;
}

void Mutator::MutateOnce(std::string* s) {
  const std::size_t at = Below(s->size() + 1);
  const std::size_t len = 1 + Below(std::min<std::size_t>(s->size() + 1, 64));
  switch (Below(11)) {
    case 0:  // flip a bit
      if (!s->empty()) {
        (*s)[Below(s->size())] ^= static_cast<char>(1u << Below(8));
      }
      break;
    case 1: {  // random bytes
      const std::size_t n = 1 + Below(8);
      std::string bytes;
      for (std::size_t i = 0; i < n; ++i) {
        bytes += static_cast<char>(Below(256));
      }
      s->insert(at, bytes);
      break;
    }
    case 2:  // delete a range
      s->erase(at, len);
      break;
    case 3: {  // duplicate a range elsewhere
      const std::string range = s->substr(at, len);
      s->insert(Below(s->size() + 1), range);
      break;
    }
    case 4: {  // repeat a range many times (a huge count, cut at max_len)
      const std::string range = s->substr(at, 1 + Below(16));
      if (range.empty()) break;
      std::string repeated;
      const std::size_t times = 2 + Below(max_len_ / range.size() + 1);
      for (std::size_t i = 0; i < times && repeated.size() < max_len_; ++i) {
        repeated += range;
      }
      s->insert(at, repeated);
      break;
    }
    case 5: {  // splice with another corpus entry
      const std::string& other = corpus_[Below(corpus_.size())];
      *s = s->substr(0, at) + other.substr(Below(other.size() + 1));
      break;
    }
    case 6:
    case 7:  // a dictionary token
      if (!dictionary_.empty()) {
        s->insert(at, dictionary_[Below(dictionary_.size())]);
      }
      break;
    case 8: {  // a number replaced by an extreme
      std::size_t begin = at;
      while (begin < s->size() && !IsNumberChar((*s)[begin])) ++begin;
      std::size_t end = begin;
      while (end < s->size() && IsNumberChar((*s)[end])) ++end;
      s->replace(begin, end - begin,
                 kExtremeNumbers[Below(kExtremeNumbers.size())]);
      break;
    }
    case 9:  // a line end, byte-order mark or control byte
      s->insert(at, kSpecialBytes[Below(kSpecialBytes.size())]);
      break;
    default:  // truncate
      s->resize(at);
      break;
  }
  if (s->size() > max_len_) s->resize(max_len_);
}

}  // namespace burrlab::fuzz
