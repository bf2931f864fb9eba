// Typed fields of a TOML table, read alike in every burrlab file kind
// (protocols, material files, station files and station scripts): one
// wording for an unknown key, a value of the wrong type, a choice outside its
// list and a number out of range, each reported where it is: an unknown key
// at the key (a [table] at its header), everything else at the value. The file
// kind decides what a report becomes: protocols and station files collect every
// one, material files keep the first.
#ifndef BURRLAB_STIMULI_TOML_FIELDS_H_
#define BURRLAB_STIMULI_TOML_FIELDS_H_

#include <toml++/toml.h>

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace burrlab::stimuli {

using TomlKeys = std::span<const std::string_view>;

// A key that changed its spelling: the old one is still read, with a note.
struct TomlRename {
  std::string_view old_key;
  std::string_view key;
};

// The type of a value as messages name it: "a string", "an integer", ...
std::string_view TomlTypeName(const toml::node& node);

// User text quoted in a message: at most 60 bytes (cut on a UTF-8 boundary,
// then "...") with control characters and bytes that are not UTF-8 escaped
// (burrlab/base/printable.h), so the message stays one line.
std::string EchoText(std::string_view text);

// `keys` joined by ", ".
std::string JoinKeys(TomlKeys keys);

// Where a node starts, as toml++ recorded it.
inline toml::source_position PositionOf(const toml::node& node) {
  return node.source().begin;
}

// The readers. Each getter returns nullopt (or null) when the key is absent,
// silently, and when its value is wrong, after reporting why. `name` is how
// the message names the field ("blocks[2].step_down", "max_force_n").
class TomlFields {
 public:
  using Report = std::function<void(toml::source_position, std::string)>;

  explicit TomlFields(Report report) : report_(std::move(report)) {}

  void Fail(toml::source_position where, std::string message) const {
    report_(where, std::move(message));
  }
  void Fail(const toml::node& node, std::string message) const {
    Fail(PositionOf(node), std::move(message));
  }

  // A report for every key of `table` (which messages call `name`: "[study]",
  // "blocks[1]", "the protocol") outside `allowed`: `unknown key "k" in name`,
  // then a did-you-mean or the accepted list. Keys in `elsewhere` get
  // `key "k" <elsewhere_message>` instead. The old spelling of a key in
  // `renamed` passes unreported and unlisted (the caller reads it with a
  // note), and a typo closest to an old spelling is pointed to its new one.
  void CheckKeys(const toml::table& table, std::string_view name,
                 TomlKeys allowed, TomlKeys elsewhere = {},
                 std::string_view elsewhere_message = {},
                 std::span<const TomlRename> renamed = {}) const;

  const toml::table* Table(const toml::table& parent, std::string_view key,
                           std::string_view name) const;
  std::optional<std::string> String(const toml::table& t, std::string_view key,
                                    std::string_view name) const;
  // An integer or a finite float, as a double.
  std::optional<double> Number(const toml::table& t, std::string_view key,
                               std::string_view name) const;
  std::optional<std::int64_t> Integer(const toml::table& t,
                                      std::string_view key,
                                      std::string_view name) const;
  std::optional<bool> Boolean(const toml::table& t, std::string_view key,
                              std::string_view name) const;
  // A string that must be one of `choices`; its index.
  std::optional<int> Choice(const toml::table& t, std::string_view key,
                            std::string_view name, TomlKeys choices) const;

  // Whether `value` (read from t[key]) lies in the interval from lo to hi,
  // open or closed at each end; reports "name must be in [lo, hi], got v" at
  // the value when it does not.
  bool Range(const toml::table& t, std::string_view key, std::string_view name,
             double value, double lo, double hi, bool lo_open,
             bool hi_open) const;

  // An integer in [lo, hi] and a number in (lo, hi]: the getter, then Range.
  std::optional<std::int64_t> IntegerIn(const toml::table& t,
                                        std::string_view key,
                                        std::string_view name, std::int64_t lo,
                                        std::int64_t hi) const;
  std::optional<double> PositiveNumberUpTo(const toml::table& t,
                                           std::string_view key,
                                           std::string_view name,
                                           double hi) const;

 private:
  Report report_;
};

}  // namespace burrlab::stimuli

#endif  // BURRLAB_STIMULI_TOML_FIELDS_H_
