// Subcommand dispatch, usage text and error lines.
#include "cli/command_table.h"

#include <fmt/format.h>

#include <algorithm>

#include "burrlab/base/spelling.h"

namespace burrlab::runner {

void PrintUsage(std::string_view path, std::span<const Command> table,
                std::ostream& out) {
  std::size_t width = 0;
  for (const Command& command : table) {
    if (command.listed) width = std::max(width, command.name.size());
  }
  out << fmt::format("usage: {} <command> [flags]\n\ncommands:\n", path);
  for (const Command& command : table) {
    if (!command.listed) continue;
    out << fmt::format("  {:<{}}  {}\n", command.name, width, command.help);
  }
  out << fmt::format("\n'{} <command> --help' shows the flags of a command.\n",
                     path);
}

int Dispatch(std::string_view path, std::span<const Command> table,
             const Args& args, std::ostream& out, std::ostream& err) {
  if (args.empty() || args[0] == "-h" || args[0] == "--help") {
    if (args.size() > 1) {
      return Fail(err, fmt::format("{} takes no further arguments, got '{}'",
                                   args[0], args[1]));
    }
    PrintUsage(path, table, out);
    return 0;
  }
  const std::string& name = args[0];
  for (const Command& command : table) {
    if (command.name == name) {
      return command.run(Args(args.begin() + 1, args.end()), out, err);
    }
  }
  if (name.starts_with("-")) {
    return Fail(err,
                fmt::format("unknown flag '{}' (see '{} --help')", name, path));
  }
  std::vector<std::string_view> names;
  for (const Command& command : table) names.push_back(command.name);
  // Name the command as typed after "burrlab", e.g. 'sim desent'.
  const std::size_t space = path.find(' ');
  const std::string lead = space == std::string_view::npos
                               ? std::string()
                               : fmt::format("{} ", path.substr(space + 1));
  if (std::string_view suggestion = DidYouMean(name, names);
      !suggestion.empty()) {
    return Fail(
        err, fmt::format("unknown command '{}{}' (did you mean '{}{}'?)", lead,
                         name, lead, suggestion));
  }
  return Fail(err, fmt::format("unknown command '{}{}' (see '{} help')", lead,
                               name, path));
}

int RunHelp(std::string_view path, std::span<const Command> table,
            const Args& args, std::ostream& out, std::ostream& err) {
  if (args.empty() || args[0] == "-h" || args[0] == "--help") {
    PrintUsage(path, table, out);
    return 0;
  }
  Args with_help = args;
  with_help.push_back("--help");
  return Dispatch(path, table, with_help, out, err);
}

int Fail(std::ostream& err, std::string_view message) {
  err << "burrlab: " << OneLine(message) << '\n';
  return 1;
}

std::string OneLine(std::string_view text) {
  std::string line;
  bool pending_space = false;
  for (char c : text) {
    if (c == '\n' || c == '\r' || c == '\t') {
      pending_space = true;
      continue;
    }
    if (pending_space && !line.empty() && line.back() != ' ') line += ' ';
    pending_space = false;
    line += c;
  }
  while (!line.empty() && line.back() == ' ') line.pop_back();
  std::size_t start = line.find_first_not_of(' ');
  return start == std::string::npos ? std::string() : line.substr(start);
}

}  // namespace burrlab::runner
