// libFuzzer's entry for one target, chosen at compile time with
// -DBURRLAB_FUZZ_TARGET=FuzzProtocol (tests/fuzz/CMakeLists.txt builds one
// executable per target). libFuzzer supplies main(). A broken property is
// printed and aborts, so libFuzzer saves the input as a crash.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data,
                                      std::size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  const burrlab::fuzz::Violations violations =
      burrlab::fuzz::BURRLAB_FUZZ_TARGET(input);
  if (violations.empty()) return 0;
  for (const std::string& v : violations) {
    std::fprintf(stderr, "property violated: %s\n", v.c_str());
  }
  std::abort();
}
