// Subcommand tables in the Ninja style: each command is a name, a one-line
// help and a handler; usage lists the table and an unknown name gets
// "did you mean ...".
#ifndef BURRLAB_RUNNER_CLI_COMMAND_TABLE_H_
#define BURRLAB_RUNNER_CLI_COMMAND_TABLE_H_

#include <ostream>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace burrlab::runner {

// A command's arguments, without the words that selected it.
using Args = std::vector<std::string>;

// Runs a command; returns the exit code (0 success, 1 any error).
using CommandHandler = int (*)(const Args& args, std::ostream& out,
                               std::ostream& err);

struct Command {
  std::string_view name;  // the word typed, e.g. "force-curve"
  std::string_view help;  // one line for the usage list
  CommandHandler run;
  // False for an old name kept so scripts still run: it dispatches but the
  // usage list leaves it out.
  bool listed = true;
};

// Prints "usage: <path> <command> [flags]" and the table.
void PrintUsage(std::string_view path, std::span<const Command> table,
                std::ostream& out);

// Runs the command named by args[0] with the remaining arguments. No
// arguments, -h or --help print the usage (exit 0); an unknown name or flag
// prints one error line with a suggestion when one is close (exit 1). `path`
// is how the table is reached, e.g. "burrlab sim".
int Dispatch(std::string_view path, std::span<const Command> table,
             const Args& args, std::ostream& out, std::ostream& err);

// The `help` command of a table: no arguments print the usage; `help NAME
// ...` runs `NAME ... --help`.
int RunHelp(std::string_view path, std::span<const Command> table,
            const Args& args, std::ostream& out, std::ostream& err);

// Prints "burrlab: <message>" as one line on `err` and returns 1.
int Fail(std::ostream& err, std::string_view message);

// `text` with every run of line breaks and tabs replaced by one space and
// surrounding blanks trimmed, so an error fits on one line.
std::string OneLine(std::string_view text);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_CLI_COMMAND_TABLE_H_
