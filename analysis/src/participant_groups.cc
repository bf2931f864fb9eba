// Subjects' groups from a BIDS participants.tsv.
#include "burrlab/analysis/participant_groups.h"

#include <fmt/format.h>

#include <algorithm>

#include "burrlab/base/file_text.h"
#include "burrlab/results_schema/records.h"
#include "csv_text.h"

namespace burrlab::analysis {

Result<ParticipantGroups> ParseParticipantGroups(std::string_view path,
                                                 std::string_view text,
                                                 std::string_view column) {
  Result<CsvTable> table = CsvTable::Split(
      path, text, CsvTable::Delimiter::kTabOrComma,
      fmt::format("the file is empty; expected a header line with "
                  "participant_id and {}",
                  column));
  if (!table.ok()) return table.error();
  const CsvTable& t = *table;
  if (Status s = t.CheckDistinctColumns(); !s.ok()) return s.error();
  std::vector<std::string> names;
  for (const Cell& c : t.header()) names.emplace_back(c.text);
  const int id_at = t.Find("participant_id");
  const int group_at = t.Find(column);
  if (id_at < 0 || group_at < 0) {
    return t.Fail(t.header_line().number, 1,
                  fmt::format("the header has no {} column (it has {})",
                              id_at < 0 ? "participant_id" : column,
                              fmt::join(names, ", ")));
  }
  ParticipantGroups out;
  out.column = std::string(column);
  std::map<std::string, int> first_line;
  for (const Line& row : t.rows()) {
    Result<std::vector<Cell>> cells = t.Cells(row);
    if (!cells.ok()) return cells.error();
    const Cell& id = (*cells)[static_cast<std::size_t>(id_at)];
    const Cell& group = (*cells)[static_cast<std::size_t>(group_at)];
    const std::string_view label =
        id.text.starts_with("sub-") ? id.text.substr(4) : std::string_view();
    if (label.empty() || !results_schema::ValidateSubjectLabel(label).ok()) {
      return t.Fail(row.number, id.column,
                    fmt::format("participant_id '{}' is not sub-<label> with "
                                "a label of letters and digits",
                                id.text));
    }
    const auto [seen, added] =
        first_line.try_emplace(std::string(label), row.number);
    if (!added) {
      return t.Fail(row.number, id.column,
                    fmt::format("{} is listed twice (first on line {})",
                                id.text, seen->second));
    }
    if (group.text.empty()) {
      return t.Fail(row.number, group.column,
                    fmt::format("{} has an empty {}; write n/a to leave it "
                                "out of the comparison",
                                id.text, column));
    }
    if (group.text == "n/a") {
      out.left_out.emplace_back(label);
      continue;
    }
    out.group_of[std::string(label)] = std::string(group.text);
    if (std::find(out.groups.begin(), out.groups.end(), group.text) ==
        out.groups.end()) {
      out.groups.emplace_back(group.text);
    }
  }
  if (out.groups.size() != 2) {
    return t.Fail(
        0, 0,
        fmt::format("the {} column holds {} group{}{}: a two-group "
                    "comparison needs exactly 2",
                    column, out.groups.size(),
                    out.groups.size() == 1 ? "" : "s",
                    out.groups.empty()
                        ? std::string()
                        : fmt::format(" ({})", fmt::join(out.groups, ", "))));
  }
  return out;
}

Result<ParticipantGroups> ReadParticipantGroups(const std::string& path,
                                                std::string_view column) {
  Result<std::string> text = ReadTextFile(path, kMaxParticipantsBytes);
  if (!text.ok()) return text.error();
  return ParseParticipantGroups(path, *text, column);
}

}  // namespace burrlab::analysis
