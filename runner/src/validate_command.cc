// burrlab validate.
#include "validate_command.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "burrlab/protocols/protocol.h"
#include "flags.h"
#include "session.h"

namespace burrlab::runner {

int RunValidateCommand(const Args& args, std::ostream& out, std::ostream& err) {
  CLI::App app{
      "Check protocol files (format burrlab-protocol/1): types, ranges, "
      "unknown keys, unknown materials and axes, designs that cannot be "
      "balanced, staircases that can never stop. Every problem is printed "
      "as path:line:col: error: ... with the source line and a caret.",
      "burrlab validate"};
  std::vector<std::string> files;
  app.add_option("files", files, "protocol files")->required();
  FlagSet flags(&app);
  if (std::optional<int> code = flags.Parse(args, out, err)) return *code;
  if (Status s = flags.Convert(); !s.ok()) return Fail(err, s.error().message);
  int code = 0;
  for (const std::string& file : files) {
    Result<LoadedProtocol> loaded = LoadProtocol(file);
    if (!loaded.ok()) {
      code = ReportLoadError(err, loaded.error());
      continue;
    }
    const protocols::Protocol& p = loaded->protocol;
    out << fmt::format("{}: ok ({} block{}, study \"{}\")\n", file,
                       p.blocks.size(), p.blocks.size() == 1 ? "" : "s",
                       p.study_name);
  }
  return code;
}

}  // namespace burrlab::runner
