// Which group each subject belongs to, from a BIDS participants.tsv (one row
// per subject: participant_id "sub-<label>" and a column naming the group,
// e.g. "expert" or "trainee"), for comparing two groups as dissertation §12.3
// compares expert surgeons' and trainees' forces and speeds.
#ifndef BURRLAB_ANALYSIS_PARTICIPANT_GROUPS_H_
#define BURRLAB_ANALYSIS_PARTICIPANT_GROUPS_H_

#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "burrlab/base/result.h"

namespace burrlab::analysis {

struct ParticipantGroups {
  std::string column;               // the group column read
  std::vector<std::string> groups;  // the two groups, in order of first row
  // Subject label (without "sub-") -> its group.
  std::map<std::string, std::string> group_of;
  // Labels whose group is n/a: listed, left out of the comparison.
  std::vector<std::string> left_out;
};

// Parses participants.tsv text; `path` names it in errors. Tab-separated
// (comma-separated when the header has no tab), a header row with
// participant_id and `column` (other columns ignored); a UTF-8 byte-order
// mark, CR LF line ends and blank lines are accepted, as in every analysis
// data file. Errors (formatted diagnostics "path:line:col: error: ...", the
// line and a caret) name: a missing column, a participant_id that is not
// sub-<letters and digits>, a participant listed twice, an empty group, and
// a column that does not hold exactly two groups.
Result<ParticipantGroups> ParseParticipantGroups(std::string_view path,
                                                 std::string_view text,
                                                 std::string_view column);

// Largest participants file read (bytes): a million participants.
inline constexpr std::uintmax_t kMaxParticipantsBytes = 64ull << 20;

// Reads and parses the file at `path`; "cannot read PATH: reason" when it
// cannot be read or is larger than kMaxParticipantsBytes.
Result<ParticipantGroups> ReadParticipantGroups(const std::string& path,
                                                std::string_view column);

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_PARTICIPANT_GROUPS_H_
