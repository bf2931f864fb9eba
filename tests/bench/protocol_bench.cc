// `burrlab validate` on a hostile protocol: a valid study with N unknown keys
// (one line each), parsed and its diagnostics formatted (the first 100 and a
// count). The time should grow linearly in N; before the line index and the
// cap, formatting every diagnostic scanned the file from its start, and
// 20,000 keys took 2.7 s.
#include <benchmark/benchmark.h>

#include <string>

#include "burrlab/protocols/protocol.h"

namespace burrlab::protocols {
namespace {

std::string BadKeys(int n) {
  std::string text =
      "format = \"burrlab-protocol/1\"\n[study]\nname = \"t\"\n"
      "[materials.pvc]\nbuiltin = \"pvc_k70\"\n"
      "[materials.bone]\nbuiltin = \"human_temporal_bone\"\n"
      "[[blocks]]\nmethod = \"same_different\"\ntask = \"probe\"\n"
      "a = \"pvc\"\nb = \"bone\"\n[observer]\n";
  for (int i = 0; i < n; ++i) {
    text += 'k';
    text += std::to_string(i);
    text += "=1\n";
  }
  return text;
}

void ValidateBadKeys(benchmark::State& state) {
  const std::string text = BadKeys(static_cast<int>(state.range(0)));
  std::size_t printed = 0;
  for (auto _ : state) {
    const ParseOutcome outcome = ParseProtocol("bad.toml", text);
    const std::string out =
        FormatDiagnostics("bad.toml", text, outcome.diagnostics);
    printed = out.size();
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["bytes_in"] = static_cast<double>(text.size());
  state.counters["bytes_printed"] = static_cast<double>(printed);
  state.SetComplexityN(state.range(0));
}

BENCHMARK(ValidateBadKeys)
    ->Arg(10000)
    ->Arg(30000)
    ->Arg(100000)
    ->Unit(benchmark::kMillisecond)
    ->Complexity(benchmark::oN);

}  // namespace
}  // namespace burrlab::protocols
