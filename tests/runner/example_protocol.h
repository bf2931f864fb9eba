// The example protocols (protocols/examples/) for the runner tests: their
// paths, and parsed. Needs only the studies layer (studies/session.h), so the
// studies tests use it without the CLI.
#ifndef BURRLAB_TESTS_RUNNER_EXAMPLE_PROTOCOL_H_
#define BURRLAB_TESTS_RUNNER_EXAMPLE_PROTOCOL_H_

#include <gtest/gtest.h>

#include <string>

#include "studies/session.h"

namespace burrlab::runner {

// The path of protocols/examples/`name` in the source tree.
inline std::string ExamplePath(const std::string& name) {
  return std::string(BURRLAB_SOURCE_DIR) + "/protocols/examples/" + name;
}

// protocols/examples/`name`, parsed (a failed expectation when it is not).
inline protocols::Protocol ExampleProtocol(const std::string& name) {
  Result<LoadedProtocol> loaded = LoadProtocol(ExamplePath(name));
  EXPECT_TRUE(loaded.ok()) << loaded.error().message;
  return loaded.ok() ? loaded->protocol : protocols::Protocol{};
}

}  // namespace burrlab::runner

#endif  // BURRLAB_TESTS_RUNNER_EXAMPLE_PROTOCOL_H_
