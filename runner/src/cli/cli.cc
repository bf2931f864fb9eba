// The top-level command table and RunCli: --version, help, dispatch, and the
// guarantee that nothing is thrown past RunCli.
#include "burrlab/runner/cli.h"

#include <exception>
#include <string_view>

#include "burrlab/base/spelling.h"
#include "burrlab_version.h"
#include "cli/analyze_commands.h"
#include "cli/calibrate_command.h"
#include "cli/command_table.h"
#include "cli/demo_command.h"
#include "cli/devices_command.h"
#include "cli/discover_command.h"
#include "cli/session_commands.h"
#include "cli/sim_commands.h"
#include "cli/validate_command.h"

namespace burrlab::runner {
namespace {

int RunTopHelp(const Args& args, std::ostream& out, std::ostream& err);

// Every command of `burrlab`, as the usage list shows them.
constexpr Command kCommands[] = {
    {"demo",
     "re-run the dissertation's chapter 13 study with simulated subjects: "
     "fit, simulate, analyse, compare",
     RunDemoCommand},
    {"validate",
     "check protocol files; print every problem with its line and column",
     RunValidateCommand},
    {"plan",
     "print the trials a protocol produces for a seed and scripted responses",
     RunPlanCommand},
    {"run",
     "run one subject's session (simulated observer or typed answers); "
     "--resume continues it",
     RunRunCommand},
    {"study", "run a population of simulated subjects", RunStudyCommand},
    {"sim",
     "burr simulator tools: force-curve, descent, measure, bench, materials",
     RunSimCommand},
    {"analyze",
     "statistics: fit, dprime, scores, thresholds, kinematics, power, "
     "fit-observers",
     RunAnalyzeCommand},
    {"calibrate",
     "fit c_e and alpha to measured descent velocities, with identifiability "
     "and profile-likelihood intervals",
     RunCalibrateCommand},
    {"discover",
     "find what the base model misses in measured descent velocities: "
     "gap, effect, report (JSON, Markdown, plots); 'discover matrix': its "
     "power against SNR and false-discovery rate (slow)",
     RunDiscoverCommand},
    // The scenario matrix's old name.
    {"discover-matrix", "the old name of 'discover matrix'",
     RunDiscoverMatrixCommand, /*listed=*/false},
    {"devices",
     "list USB and HID devices with their ids and the backend that fits",
     RunDevicesCommand},
    {"help", "list the commands; 'help COMMAND' shows the flags of one",
     RunTopHelp},
};

int RunTopHelp(const Args& args, std::ostream& out, std::ostream& err) {
  return RunHelp("burrlab", kCommands, args, out, err);
}

int RunTopLevel(const Args& args, std::ostream& out, std::ostream& err) {
  if (!args.empty() && args[0] == "--version") {
    if (args.size() > 1) {
      return Fail(
          err, "--version takes no further arguments, got '" + args[1] + "'");
    }
    out << "burrlab " << BURRLAB_VERSION << '\n';
    return 0;
  }
  if (!args.empty() && args[0].starts_with("-") && args[0] != "-h" &&
      args[0] != "--help") {
    constexpr std::string_view kFlags[] = {"--help", "--version"};
    const std::string flag = args[0].substr(0, args[0].find('='));
    if (std::string_view suggestion = DidYouMean(flag, kFlags);
        !suggestion.empty()) {
      return Fail(err, "unknown flag '" + flag + "' (did you mean '" +
                           std::string(suggestion) + "'?)");
    }
    return Fail(err, "unknown flag '" + flag + "' (see 'burrlab --help')");
  }
  return Dispatch("burrlab", kCommands, args, out, err);
}

}  // namespace

int RunCli(const std::vector<std::string>& args, std::ostream& out,
           std::ostream& err) {
  int code = 1;
  try {
    code = RunTopLevel(args, out, err);
  } catch (const std::exception& e) {
    return Fail(err, std::string("internal error: ") + e.what());
  } catch (...) {
    return Fail(err, "internal error: unknown exception");
  }
  out.flush();
  if (code == 0 && !out.good()) {
    return Fail(err, "cannot write to standard output");
  }
  return code;
}

}  // namespace burrlab::runner
