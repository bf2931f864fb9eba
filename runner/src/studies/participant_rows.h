// What burrlab's runs write into a dataset's participants.tsv
// (results_schema/participants.h): the experimenter's values of the subject
// and, for a simulated subject, the true parameters of its simulated
// observer, in columns observer_* that participants.json describes with
// their units.
#ifndef BURRLAB_RUNNER_STUDIES_PARTICIPANT_ROWS_H_
#define BURRLAB_RUNNER_STUDIES_PARTICIPANT_ROWS_H_

#include <string>
#include <vector>

#include "burrlab/protocols/observer.h"
#include "burrlab/results_schema/participants.h"

namespace burrlab::runner {

// Columns of a simulated observer's parameters, described for
// participants.json: observer_weber_stiffness, observer_weber_removal,
// observer_lapse, observer_criterion, observer_rule, observer_rt_median (s),
// observer_rt_log_sd, observer_match_tolerance and observer_answers.
const std::vector<results_schema::ParticipantColumn>&
ObserverParticipantColumns();

// The values of those columns for `observer` (shortest decimal text that
// reads back exactly).
std::vector<results_schema::ParticipantValue> ObserverParticipantValues(
    const protocols::ObserverParams& observer);

// True for a column name burrlab fills itself (observer_*), which the
// experimenter's values may not use.
bool IsObserverColumn(const std::string& column);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_STUDIES_PARTICIPANT_ROWS_H_
