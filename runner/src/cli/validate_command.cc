// burrlab validate.
#include "cli/validate_command.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "burrlab/base/file_text.h"
#include "burrlab/base/printable.h"
#include "burrlab/protocols/protocol.h"
#include "burrlab/protocols/protocol_file.h"
#include "burrlab/stimuli/interval.h"
#include "cli/flags.h"
#include "station/station_file.h"
#include "studies/session.h"

namespace burrlab::runner {
namespace {

// Station files are small; anything larger is refused before reading.
constexpr std::uintmax_t kMaxStationBytes = 64 * 1024;

// Validates `file` when it is a station file: true with `code` set when it
// was one (or could not be read), false to treat it as a protocol.
bool ValidateIfStation(const std::string& file, std::ostream& out,
                       std::ostream& err, int* code) {
  std::variant<std::string, FileReadFailure> read =
      ReadFileBytes(file, kMaxStationBytes, FileKinds::kRegularOnly);
  const std::string* text = std::get_if<std::string>(&read);
  // What cannot be read here is read again, and reported, as a protocol.
  if (text == nullptr || !LooksLikeStationFile(*text)) return false;
  StationParseOutcome parsed = ParseStation(file, *text);
  if (!parsed.station.has_value()) {
    err << protocols::FormatDiagnostics(file, *text, parsed.diagnostics);
    *code = 1;
    return true;
  }
  const StationConfig& s = *parsed.station;
  out << fmt::format(
      "{}: ok (station: device {}, max force {} N, {}screen {}x{})\n", file,
      s.device, s.max_force_n,
      s.response_box.has_value()
          ? fmt::format("response box {:04x}:{:04x} with {} button{}, ",
                        s.response_box->vendor_id, s.response_box->product_id,
                        s.response_box->buttons.size(),
                        s.response_box->buttons.size() == 1 ? "" : "s")
          : std::string(),
      s.screen_width, s.screen_height);
  return true;
}

}  // namespace

int RunValidateCommand(const Args& args, std::ostream& out, std::ostream& err) {
  CLI::App app{
      "Check protocol files (format burrlab-protocol/1) and station files "
      "(burrlab-station/1): types, ranges, "
      "unknown keys, unknown materials and axes, designs that cannot be "
      "balanced, staircases that can never stop, and every level a block "
      "can reach (adaptive tracks to their floor and ceiling, or as far as "
      "max_trials steps go): its material must be one the simulator renders "
      "with the simulated hand at --radius-mm, so a protocol that validates "
      "runs. Every problem is printed as path:line:col: error: ... with the "
      "source line and a caret (at most 100, then a count).",
      "burrlab validate"};
  std::vector<std::string> files;
  app.add_option("files", files, "protocol or station files")->required();
  double radius_mm = stimuli::kDefaultBurrRadiusMm;
  FlagSet flags(&app);
  flags.AddPositive("--radius-mm",
                    fmt::format("burr radius the simulated intervals are "
                                "checked with (default {:g}, as run and study "
                                "use)",
                                stimuli::kDefaultBurrRadiusMm),
                    "mm", &radius_mm, 5.0);
  if (std::optional<int> code = flags.Parse(args, out, err)) return *code;
  if (Status s = flags.Convert(); !s.ok()) return Fail(err, s.error().message);
  int code = 0;
  for (const std::string& file : files) {
    if (ValidateIfStation(file, out, err, &code)) continue;
    Result<protocols::LoadedProtocol> loaded = protocols::LoadProtocol(file);
    if (!loaded.ok()) {
      code = ReportLoadError(err, loaded.error());
      continue;
    }
    err << loaded->notes;
    if (Status s = CheckRenderable(loaded.value(), radius_mm); !s.ok()) {
      code = ReportLoadError(err, s.error());
      continue;
    }
    const protocols::Protocol& p = loaded->protocol;
    out << fmt::format("{}: ok ({} block{}, study \"{}\")\n", file,
                       p.blocks.size(), p.blocks.size() == 1 ? "" : "s",
                       PrintableText(p.study_name));
  }
  return code;
}

}  // namespace burrlab::runner
