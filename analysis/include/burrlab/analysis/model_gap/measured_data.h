// Measured burring data for calibration: one penetration velocity per run of
// the constant-force descent rig (dissertation §8.6), read from a CSV whose
// header holds force_n and velocity_mm_s and optionally run, material,
// burr_radius_mm, spindle_rad_s and velocity_definition (other columns are
// ignored). Replicate runs at a force level are expected. Parsers take
// (path, text) so tests need no files; errors read
// "path:line:col: error: message", then the source line and a caret.
#ifndef BURRLAB_ANALYSIS_MODEL_GAP_MEASURED_DATA_H_
#define BURRLAB_ANALYSIS_MODEL_GAP_MEASURED_DATA_H_

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "burrlab/base/result.h"
#include "burrlab/sim/descent.h"

namespace burrlab::analysis {

// One run: the force held and the steady velocity measured.
struct MeasuredRun {
  double force_n = 0.0;        // force held by the rig, > 0
  double velocity_mm_s = 0.0;  // steady penetration velocity, > 0
  std::string run;             // the run column, or "" when absent
  std::string material;        // the material column, or ""
  int line = 0;                // 1-based line in the file
};

struct MeasuredData {
  std::vector<MeasuredRun> runs;  // in file order
  int force_levels = 0;           // distinct force_n values
  // The burr radius when the file has a burr_radius_mm column (one value for
  // every run); the spindle speed likewise.
  std::optional<double> burr_radius_mm;
  std::optional<double> spindle_rad_s;
  // What the velocities are (sim/descent.h) when the file has a
  // velocity_definition column (one value for every run), and its first
  // data line.
  std::optional<sim::VelocityDefinition> velocity_definition;
  int velocity_definition_line = 0;
};

// The parameters fitted from v(F): c_e and alpha. Data with fewer runs than
// parameters + 1 leave no degree of freedom for the error and are refused.
inline constexpr int kCalibrationParameters = 2;

// Parses `text` (the whole file). Cells are trimmed; blank lines, CR line ends
// and a UTF-8 byte-order mark are accepted. force_n and velocity_mm_s must be
// positive finite numbers (log-velocity fits need v > 0), burr_radius_mm
// positive and spindle_rad_s zero or positive, velocity_definition "initial"
// or "settled", each the same on every row;
// the data need at least two force levels and more runs than parameters. The
// error is a formatted diagnostic (up to three lines).
Result<MeasuredData> ParseMeasuredData(std::string_view path,
                                       std::string_view text);

// Refuses data whose velocity_definition column names another definition
// than `model`, the one the fit predicts, naming both; data without the
// column are taken to be `model`'s.
Status CheckVelocityDefinition(std::string_view path, const MeasuredData& data,
                               sim::VelocityDefinition model);

// Reads and parses the file at `path`; "cannot read PATH: reason" when it
// cannot be read.
Result<MeasuredData> ReadMeasuredData(const std::string& path);

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_MODEL_GAP_MEASURED_DATA_H_
