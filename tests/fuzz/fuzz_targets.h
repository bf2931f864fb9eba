// Property-based fuzz targets, one per parser of untrusted input: each takes
// arbitrary bytes, runs the parser as the product does, and checks properties
// of what comes back (an error of the documented kind with a printable message
// that names the file and, for formats with lines, a line that exists; or a
// value that satisfies the format's invariants). The same targets run under
// libFuzzer (libfuzzer_entry.cc, `make fuzz`) and in the test suite with a
// deterministic mutator (fuzz_test.cc). README.md in this folder lists the
// properties per target.
#ifndef BURRLAB_TESTS_FUZZ_FUZZ_TARGETS_H_
#define BURRLAB_TESTS_FUZZ_FUZZ_TARGETS_H_

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace burrlab::fuzz {

// What a target found wrong on one input, one line per broken property; empty
// when every property held. An exception escaping the parser is one too.
using Violations = std::vector<std::string>;

using TargetFunction = Violations (*)(std::string_view input);

struct Target {
  std::string_view name;  // also the corpus folder: corpus/<name>/
  TargetFunction run;
  std::size_t max_len;  // longest input worth trying (bytes)
};

// Every target, in a fixed order.
std::span<const Target> Targets();

// The targets, callable one by one (libFuzzer builds one executable each).
Violations FuzzProtocol(std::string_view input);
Violations FuzzStation(std::string_view input);
Violations FuzzStationScript(std::string_view input);
Violations FuzzMaterial(std::string_view input);
Violations FuzzNrrd(std::string_view input);
Violations FuzzMeasured(std::string_view input);
Violations FuzzTraces(std::string_view input);
Violations FuzzPsychometric(std::string_view input);
Violations FuzzBehTsv(std::string_view input);
Violations FuzzPhysioSidecar(std::string_view input);
Violations FuzzPhysioRows(std::string_view input);
Violations FuzzParticipants(std::string_view input);

}  // namespace burrlab::fuzz

#endif  // BURRLAB_TESTS_FUZZ_FUZZ_TARGETS_H_
