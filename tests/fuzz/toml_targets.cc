// Fuzz targets of the TOML formats: protocol files (parse, then what
// `burrlab validate` and a run do with a parsed protocol), station files,
// station scripts and material files.
#include <algorithm>
#include <cmath>
#include <numeric>

#include "burrlab/protocols/protocol.h"
#include "burrlab/stimuli/materials.h"
#include "fuzz_targets.h"
#include "property_checks.h"
#include "station/station_file.h"
#include "station/station_script.h"

namespace burrlab::fuzz {
namespace {

// Burr radius `burrlab validate` checks simulated intervals with by default.
constexpr double kValidateRadiusMm = 2.0;

void CheckProtocol(const protocols::Protocol& p, std::string_view input,
                   Violations* v) {
  Expect(p.format == protocols::kProtocolFormat,
         "protocol: parsed with another format", v);
  Expect(!p.blocks.empty(), "protocol: parsed without blocks", v);
  Expect(p.trace_hz > 0 && 1000 % p.trace_hz == 0,
         "protocol: trace_hz does not divide 1000", v);
  for (const protocols::ProtocolMaterial& m : p.materials) {
    Expect(m.set.material.Validate().ok(),
           "protocol: a material parsed with invalid parameters", v);
  }
  for (const protocols::Axis& axis : p.axes) {
    const auto [lo, hi] = protocols::AxisDomain(p, axis);
    Expect(std::isfinite(lo) && std::isfinite(hi) && lo <= hi,
           "protocol: an axis domain is not a finite range", v);
  }
  for (const protocols::Block& b : p.blocks) {
    for (double s : b.interval_s) {
      Expect(std::isfinite(s) && s >= 0.0,
             "protocol: an interval duration is not finite and >= 0", v);
    }
    if (!b.axis.empty()) {
      Expect(std::isfinite(b.standard_level),
             "protocol: a standard level is not finite", v);
    }
  }
  // Block orders are permutations of the blocks for any subject.
  for (int subject : {0, 1, 2, 5}) {
    std::vector<int> order = protocols::BlockOrder(p, subject);
    std::sort(order.begin(), order.end());
    std::vector<int> all(p.blocks.size());
    std::iota(all.begin(), all.end(), 0);
    Expect(order == all, "protocol: a block order is not a permutation", v);
  }
  // What `burrlab validate` and every simulated run check next.
  const std::vector<protocols::Diagnostic> rendering =
      protocols::CheckSimulatedIntervals(p, kValidateRadiusMm);
  CheckDiagnostics(rendering, input, v);
}

}  // namespace

Violations FuzzProtocol(std::string_view input) {
  return Guarded("protocol", [&](Violations* v) {
    const protocols::ParseOutcome outcome =
        protocols::ParseProtocol(kInputPath, input);
    Expect(outcome.protocol.has_value() == outcome.diagnostics.empty(),
           "protocol: a protocol comes back exactly when there are no "
           "diagnostics",
           v);
    CheckDiagnostics(outcome.diagnostics, input, v);
    Expect(
        std::is_sorted(outcome.diagnostics.begin(), outcome.diagnostics.end(),
                       [](const auto& a, const auto& b) {
                         return std::pair{a.where.line, a.where.column} <
                                std::pair{b.where.line, b.where.column};
                       }),
        "protocol: diagnostics are not in file order", v);
    if (outcome.protocol.has_value())
      CheckProtocol(*outcome.protocol, input, v);
  });
}

Violations FuzzStation(std::string_view input) {
  return Guarded("station", [&](Violations* v) {
    const runner::StationParseOutcome outcome =
        runner::ParseStation(kInputPath, input);
    Expect(outcome.station.has_value() == outcome.diagnostics.empty(),
           "station: a station comes back exactly when there are no "
           "diagnostics",
           v);
    CheckDiagnostics(outcome.diagnostics, input, v);
    if (!outcome.station.has_value()) return;
    const runner::StationConfig& s = *outcome.station;
    Expect(s.device == "mouse" || s.device == "hid" || s.device == "falcon" ||
               s.device == "simulated",
           "station: unknown device accepted", v);
    Expect(s.max_force_n > 0.0 && s.max_force_n <= 20.0,
           "station: max_force_n outside (0, 20]", v);
    Expect(s.max_stiffness_n_per_mm >= 0.0 && s.max_stiffness_n_per_mm <= 50.0,
           "station: max_stiffness_n_per_mm outside [0, 50]", v);
    Expect(s.screen_width > 0 && s.screen_height > 0,
           "station: a screen size is not positive", v);
    if (s.response_box.has_value()) {
      Expect(s.response_box->Validate().ok(),
             "station: the response box options do not validate", v);
    }
  });
}

Violations FuzzStationScript(std::string_view input) {
  return Guarded("station_script", [&](Violations* v) {
    const runner::StationScriptParseOutcome outcome =
        runner::ParseStationScript(kInputPath, input);
    Expect(outcome.script.has_value() == outcome.diagnostics.empty(),
           "station_script: a script comes back exactly when there are no "
           "diagnostics",
           v);
    CheckDiagnostics(outcome.diagnostics, input, v);
    if (!outcome.script.has_value()) return;
    const runner::StationScript& s = *outcome.script;
    Expect(!s.path.empty(), "station_script: an empty path accepted", v);
    for (std::size_t k = 0; k < s.path.size(); ++k) {
      const runner::Waypoint& w = s.path[k];
      Expect(std::isfinite(w.t_s) && std::isfinite(w.position_mm.x) &&
                 std::isfinite(w.position_mm.y) &&
                 std::isfinite(w.position_mm.z),
             "station_script: a waypoint is not finite", v);
      if (k > 0) {
        Expect(w.t_s >= s.path[k - 1].t_s,
               "station_script: waypoint times go back", v);
      }
    }
    Expect(std::isfinite(s.start_delay_s) && s.start_delay_s >= 0.0 &&
               std::isfinite(s.response_delay_s) && s.response_delay_s >= 0.0,
           "station_script: a delay is not a finite time >= 0", v);
    for (const runner::ScriptedUnplug& u : s.unplugs) {
      Expect(u.presentation >= 1 && u.interval >= 1 &&
                 std::isfinite(u.after_s) && u.after_s >= 0.0,
             "station_script: an unplug outside its ranges", v);
    }
  });
}

Violations FuzzMaterial(std::string_view input) {
  return Guarded("material", [&](Violations* v) {
    const Result<stimuli::MaterialSet> set =
        stimuli::ParseMaterial(kInputPath, input);
    if (!set.ok()) {
      CheckFormattedError(set.error().message, input, "material", v);
      return;
    }
    Expect(set->material.Validate().ok(),
           "material: parsed parameters do not validate", v);
    Expect(!set->name.empty(), "material: parsed without a name", v);
  });
}

}  // namespace burrlab::fuzz
