// Fuzz targets of the data formats: NRRD volumes, the CSV/TSV readers of
// analysis (measured descent velocities, descent traces, psychometric data)
// and of results_schema (_beh.tsv, _physio.json sidecars, _physio.tsv rows,
// the participants table an experimenter keeps).
#include <cmath>
#include <set>

#include "burrlab/analysis/model_gap/measured_data.h"
#include "burrlab/analysis/model_gap/trace_data.h"
#include "burrlab/analysis/psychometric_data.h"
#include "burrlab/results_schema/bids_read.h"
#include "burrlab/results_schema/participants.h"
#include "burrlab/results_schema/records.h"
#include "burrlab/sim/nrrd.h"
#include "fuzz_targets.h"
#include "property_checks.h"

namespace burrlab::fuzz {
namespace {

bool FiniteAndPositive(double x) { return std::isfinite(x) && x > 0.0; }

// An error of a parser that names the input first ("input: ..." or
// "input:line:col: error: ...").
template <typename AnyResult>
bool Failed(const AnyResult& result, std::string_view input,
            std::string_view what, Violations* v) {
  if (result.ok()) return false;
  CheckFormattedError(result.error().message, input, what, v);
  return true;
}

}  // namespace

Violations FuzzNrrd(std::string_view input) {
  return Guarded("nrrd", [&](Violations* v) {
    // Both mappings `burrlab sim` offers.
    sim::IntensityMapping linear;
    linear.kind = sim::IntensityMapping::Kind::kLinear;
    linear.low = 100.0;
    linear.high = 1000.0;
    for (const sim::IntensityMapping& mapping :
         {sim::IntensityMapping{}, linear}) {
      const Result<sim::Volume> volume =
          sim::ParseNrrd(kInputPath, input, mapping);
      if (!volume.ok()) {
        // NRRD errors are one line: "input: what" (a header line is named
        // inside the message).
        CheckFormattedError(volume.error().message, input, "nrrd", v);
        CheckMessageLine(volume.error().message, "nrrd", v);
        continue;
      }
      const std::size_t voxels = static_cast<std::size_t>(volume->nx()) *
                                 static_cast<std::size_t>(volume->ny()) *
                                 static_cast<std::size_t>(volume->nz());
      Expect(volume->nx() >= 1 && volume->ny() >= 1 && volume->nz() >= 1 &&
                 voxels <= sim::kMaxVolumeVoxels,
             "nrrd: parsed extents outside 1..kMaxVolumeVoxels", v);
      Expect(FiniteAndPositive(volume->voxel_mm()),
             "nrrd: parsed voxel size is not finite and positive", v);
      // Raw data are present in the input; gzip data inflate at most
      // 1100-fold (nrrd.cc: kMaxInflateRatio): no more voxels than that.
      Expect(voxels <= 1100 * input.size() + 1100,
             "nrrd: more voxels than the input can hold", v);
    }
  });
}

Violations FuzzMeasured(std::string_view input) {
  return Guarded("measured", [&](Violations* v) {
    const Result<analysis::MeasuredData> data =
        analysis::ParseMeasuredData(kInputPath, input);
    if (Failed(data, input, "measured", v)) return;
    Expect(
        static_cast<int>(data->runs.size()) > analysis::kCalibrationParameters,
        "measured: no more runs than fitted parameters", v);
    Expect(data->force_levels >= 2, "measured: fewer than two force levels", v);
    const int lines = CountLines(input);
    for (const analysis::MeasuredRun& r : data->runs) {
      Expect(FiniteAndPositive(r.force_n) && FiniteAndPositive(r.velocity_mm_s),
             "measured: a force or velocity is not finite and positive", v);
      Expect(r.line >= 1 && r.line <= lines, "measured: a run's line is wrong",
             v);
    }
    if (data->burr_radius_mm) {
      Expect(FiniteAndPositive(*data->burr_radius_mm),
             "measured: burr radius not finite and positive", v);
    }
    if (data->spindle_rad_s) {
      Expect(std::isfinite(*data->spindle_rad_s) && *data->spindle_rad_s >= 0,
             "measured: spindle speed not finite and >= 0", v);
    }
    for (sim::VelocityDefinition model : {sim::VelocityDefinition::kInitial,
                                          sim::VelocityDefinition::kSettled}) {
      const Status s =
          analysis::CheckVelocityDefinition(kInputPath, *data, model);
      if (!s.ok()) {
        CheckFormattedError(s.error().message, input, "measured definition", v);
      }
    }
  });
}

Violations FuzzTraces(std::string_view input) {
  return Guarded("traces", [&](Violations* v) {
    const Result<analysis::TraceData> data =
        analysis::ParseTraceData(kInputPath, input);
    if (Failed(data, input, "traces", v)) return;
    for (const analysis::RunTrace& r : data->runs) {
      Expect(r.t_s.size() >= 2 && r.force_n.size() == r.t_s.size() &&
                 r.depth_mm.size() == r.t_s.size(),
             "traces: a run has fewer than 2 samples or ragged columns", v);
      for (std::size_t k = 0; k < r.t_s.size(); ++k) {
        Expect(std::isfinite(r.t_s[k]) && std::isfinite(r.force_n[k]) &&
                   std::isfinite(r.depth_mm[k]),
               "traces: a sample is not finite", v);
        if (k > 0) {
          Expect(r.t_s[k] > r.t_s[k - 1],
                 "traces: time does not increase within a run", v);
        }
      }
    }
    // Matching against measured data with none of its runs names the file.
    analysis::MeasuredData none;
    const Status matched =
        analysis::MatchTracesToRuns(*data, none, kInputPath, input);
    if (!matched.ok()) {
      CheckFormattedError(matched.error().message, input, "traces match", v);
    }
  });
}

Violations FuzzPsychometric(std::string_view input) {
  return Guarded("psychometric", [&](Violations* v) {
    const Result<analysis::PsychometricDataFile> data =
        analysis::ParsePsychometricData(kInputPath, input);
    if (Failed(data, input, "psychometric", v)) return;
    for (std::size_t k = 0; k < data->blocks.size(); ++k) {
      const analysis::DataBlock& b = data->blocks[k];
      Expect(std::isfinite(b.level), "psychometric: a level is not finite", v);
      Expect(b.n_total >= 1 && b.n_correct >= 0 && b.n_correct <= b.n_total,
             "psychometric: counts outside 0 <= n_correct <= n_total, "
             "n_total >= 1",
             v);
      if (k > 0) {
        Expect(b.level > data->blocks[k - 1].level,
               "psychometric: levels not strictly increasing", v);
      }
    }
  });
}

Violations FuzzBehTsv(std::string_view input) {
  return Guarded("beh_tsv", [&](Violations* v) {
    const Result<results_schema::BehTable> table =
        results_schema::ParseBehTsv(kInputPath, input);
    if (Failed(table, input, "beh_tsv", v)) return;
    Expect(!table.value().trials.empty(), "beh_tsv: parsed without trials", v);
    int previous = -1;
    for (const results_schema::TrialRecord& t : table.value().trials) {
      Expect(t.trial_index > previous, "beh_tsv: trial indices not increasing",
             v);
      previous = t.trial_index;
      for (const std::optional<double>& x :
           {t.stim_level, t.response_time_s, t.step_size, t.estimate}) {
        Expect(!x || std::isfinite(*x), "beh_tsv: a number is not finite", v);
      }
      Expect(!t.response_time_s || *t.response_time_s >= 0.0,
             "beh_tsv: a negative response time", v);
      Expect(results_schema::IsKnownTask(t.task),
             "beh_tsv: an unknown task accepted", v);
    }
  });
}

Violations FuzzParticipants(std::string_view input) {
  return Guarded("participants", [&](Violations* v) {
    // `--participant KEY=VALUE`: the input's first line as one pair.
    const std::string_view pair = input.substr(0, input.find('\n'));
    const Result<results_schema::ParticipantValue> one =
        results_schema::ParseParticipantPair(pair);
    if (!one.ok()) {
      CheckMessageLine(one.error().message, "participants: a pair's error", v);
    } else {
      Expect(results_schema::CheckParticipantColumn(one->column).ok() &&
                 results_schema::CheckParticipantValue(one->column, one->value)
                     .ok(),
             "participants: a pair that its own checks refuse", v);
    }
    // `--participants FILE`.
    const Result<std::vector<results_schema::ParticipantRow>> rows =
        results_schema::ParseParticipantsTable(kInputPath, input);
    if (Failed(rows, input, "participants", v)) return;
    std::set<std::string> subjects;
    for (const results_schema::ParticipantRow& row : rows.value()) {
      Expect(results_schema::ValidateSubjectLabel(row.subject).ok(),
             "participants: a subject label that is not a label", v);
      Expect(subjects.insert(row.subject).second,
             "participants: a subject listed twice", v);
      std::set<std::string> columns;
      for (const results_schema::ParticipantValue& c : row.values) {
        Expect(columns.insert(c.column).second,
               "participants: a column twice in one row", v);
        Expect(results_schema::CheckParticipantColumn(c.column).ok(),
               "participants: a column its own check refuses (a name, a date "
               "of birth, participant_id or not snake_case)",
               v);
        Expect(results_schema::CheckParticipantValue(c.column, c.value).ok(),
               "participants: a cell its own check refuses", v);
      }
    }
  });
}

Violations FuzzPhysioSidecar(std::string_view input) {
  return Guarded("physio_sidecar", [&](Violations* v) {
    const Result<results_schema::PhysioFile> file =
        results_schema::ParsePhysioSidecar("input_physio.json", input);
    if (!file.ok()) {
      Expect(file.error().message.starts_with("input_physio.json:"),
             "physio_sidecar: the error does not name the file", v);
      CheckMessageLine(file.error().message, "physio_sidecar", v);
      return;
    }
    Expect(FiniteAndPositive(file.value().sampling_frequency_hz),
           "physio_sidecar: sampling frequency not finite and positive", v);
    Expect(std::isfinite(file.value().start_time_s),
           "physio_sidecar: start time not finite", v);
    Expect(!file.value().columns.empty(), "physio_sidecar: no columns", v);
    Expect(file.value().data_path.filename() == "input_physio.tsv.gz",
           "physio_sidecar: the data file is not the sidecar's .tsv.gz", v);
  });
}

Violations FuzzPhysioRows(std::string_view input) {
  return Guarded("physio_rows", [&](Violations* v) {
    // The columns of a probing block's export.
    const std::vector<std::string> columns = {
        "trial_index", "interval_index", "time",    "x_mm",
        "y_mm",        "z_mm",           "force_n", "depth_mm"};
    std::size_t rows = 0;
    const Status s = results_schema::ForEachPhysioRowOfText(
        kInputPath, columns, input, [&](std::span<const double> row) {
          ++rows;
          if (row.size() != columns.size()) {
            v->push_back("physio_rows: a row of the wrong width");
          }
          for (double x : row) {
            if (!std::isnan(x) && !std::isfinite(x)) {
              v->push_back("physio_rows: an infinite value");
            }
          }
          return rows < 100000;
        });
    if (!s.ok()) {
      CheckFormattedError(s.error().message, input, "physio_rows", v);
      CheckMessageLine(s.error().message, "physio_rows", v);
    }
  });
}

}  // namespace burrlab::fuzz
