// Subcommand table and dispatch (being written).
#include "burrlab/runner/cli.h"

namespace burrlab::runner {

int RunCli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  (void)args;
  (void)out;
  err << "burrlab: not yet implemented\n";
  return 1;
}

}  // namespace burrlab::runner
