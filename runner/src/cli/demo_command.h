// `burrlab demo`: the chapter 13 demo (studies/chapter13_demo.h) with its
// flags, and its report printed beside the dissertation's numbers.
#ifndef BURRLAB_RUNNER_CLI_DEMO_COMMAND_H_
#define BURRLAB_RUNNER_CLI_DEMO_COMMAND_H_

#include <ostream>

#include "cli/command_table.h"
#include "studies/chapter13_demo.h"

namespace burrlab::runner {

// The side-by-side table and the fitted population, as printed.
void PrintDemoReport(const DemoReport& report, const DemoOptions& options,
                     std::ostream& out);

// `burrlab demo`; args start after "demo".
int RunDemoCommand(const Args& args, std::ostream& out, std::ostream& err);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_CLI_DEMO_COMMAND_H_
