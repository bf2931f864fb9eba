// `burrlab plan`, `burrlab run` and `burrlab study`: dry-running a protocol
// with scripted responses, running one subject, running a simulated
// population.
#ifndef BURRLAB_RUNNER_CLI_SESSION_COMMANDS_H_
#define BURRLAB_RUNNER_CLI_SESSION_COMMANDS_H_

#include <ostream>
#include <string_view>

#include "cli/command_table.h"

namespace burrlab::runner {

// `burrlab plan FILE [--seed S] [--subject ID] [--responses 1,0,...] [--json]`.
int RunPlanCommand(const Args& args, std::ostream& out, std::ostream& err);
// `burrlab run FILE --subject ID --out DIR [--seed S] [--observer ...]
// [--resume] [--device mouse|hid|falcon|simulated] [--station FILE]
// [--script FILE] [--firmware FILE] [--screenshots DIR]`.
int RunRunCommand(const Args& args, std::ostream& out, std::ostream& err);
// `burrlab study FILE --simulated-subjects N --out DIR [--seed S] [--jobs J]`.
int RunStudyCommand(const Args& args, std::ostream& out, std::ostream& err);

// The counterbalancing index of a subject label: the label's number minus
// one when it is all digits ("01" -> 0, "12" -> 11), else 0.
int DefaultSubjectIndex(std::string_view label);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_CLI_SESSION_COMMANDS_H_
