// The observer_* columns of participants.tsv (see participant_rows.h).
#include "studies/participant_rows.h"

#include <fmt/format.h>

namespace burrlab::runner {

const std::vector<results_schema::ParticipantColumn>&
ObserverParticipantColumns() {
  static const std::vector<results_schema::ParticipantColumn> kColumns = {
      {"observer_weber_stiffness",
       "Simulated subjects: the simulated observer's true Weber fraction for "
       "stiffness (probe intervals), the SD of the Gaussian noise added to "
       "ln(felt stiffness); n/a for a person",
       "",
       {}},
      {"observer_weber_removal",
       "Simulated subjects: the simulated observer's true Weber fraction for "
       "the penetration rate (drill intervals), the SD of the Gaussian noise "
       "added to ln(felt rate); n/a for a person",
       "",
       {}},
      {"observer_lapse",
       "Simulated subjects: probability that the simulated observer answers "
       "a trial at random; n/a for a person",
       "",
       {}},
      {"observer_criterion",
       "Simulated subjects: decision criterion of limits trials and of "
       "same-different trials under the fixed rule, which the observer "
       "answers 'different' when its percepts differ by more than criterion "
       "x Weber fraction x sqrt(2); n/a for a person",
       "",
       {}},
      {"observer_rule",
       "Simulated subjects: how the simulated observer decides same-different "
       "trials; n/a for a person",
       "",
       {{"fixed",
         "'different' when the percepts differ by more than criterion x Weber "
         "fraction x sqrt(2), a criterion set against its own noise alone"},
        {"differencing",
         "on the difference of the percepts, with the optimal criterion for "
         "the variability it felt (its noise and each material's spread "
         "between renderings)"},
        {"likelihood",
         "the independent-observation rule: 'different' when the pair of "
         "percepts is likelier under different materials than under the "
         "same, given the variability it felt"}}},
      {"observer_bias",
       "Simulated subjects: under the differencing and likelihood rules, the "
       "ln of the prior odds of a same pair the observer assumes ('different' "
       "when the log odds of the percepts exceed it; 0: even); n/a for a "
       "person",
       "",
       {}},
      {"observer_force_factor",
       "Simulated subjects: the simulated hand's typical force (probing "
       "presses and drilling) relative to the protocol's probe_force_n and "
       "drill_force_n; n/a for a person",
       "",
       {}},
      {"observer_speed_factor",
       "Simulated subjects: the simulated hand's typical pressing speed "
       "relative to the protocol's (one press a second); n/a for a person",
       "",
       {}},
      {"observer_force_spread",
       "Simulated subjects: SD of ln(force) of the simulated hand from one "
       "interval to the next; n/a for a person",
       "",
       {}},
      {"observer_speed_spread",
       "Simulated subjects: SD of ln(pressing speed) of the simulated hand "
       "from one interval to the next; n/a for a person",
       "",
       {}},
      {"observer_rt_median",
       "Simulated subjects: median of the simulated observer's log-normal "
       "response times; n/a for a person",
       "s",
       {}},
      {"observer_rt_log_sd",
       "Simulated subjects: SD of ln(response time) of the simulated "
       "observer; n/a for a person",
       "",
       {}},
      {"observer_match_tolerance",
       "Simulated subjects: an adjustment ends when the observer's percepts "
       "differ by less than this times its Weber fraction; n/a for a person",
       "",
       {}},
      {"observer_answers",
       "Simulated subjects: what the simulated observer's answers follow; "
       "n/a for a person",
       "",
       {{"percepts", "its noisy percepts of the cues it felt"},
        {"always_correct",
         "always the correct answer ('yes' where a trial has none), to run a "
         "protocol to the ends of its levels"},
        {"always_wrong",
         "always a wrong answer ('no' where a trial has none)"}}},
  };
  return kColumns;
}

std::vector<results_schema::ParticipantValue> ObserverParticipantValues(
    const protocols::ObserverParams& o) {
  const auto number = [](double value) { return fmt::format("{}", value); };
  const char* answers =
      o.answers == protocols::AnswerRule::kAlwaysCorrect ? "always_correct"
      : o.answers == protocols::AnswerRule::kAlwaysWrong ? "always_wrong"
                                                         : "percepts";
  return {
      {"observer_weber_stiffness", number(o.weber_stiffness)},
      {"observer_weber_removal", number(o.weber_removal)},
      {"observer_lapse", number(o.lapse)},
      {"observer_criterion", number(o.criterion)},
      {"observer_rule", std::string(protocols::SameDifferentRuleName(o.rule))},
      {"observer_bias", number(o.bias)},
      {"observer_force_factor", number(o.exploration.force_factor)},
      {"observer_speed_factor", number(o.exploration.speed_factor)},
      {"observer_force_spread", number(o.exploration.force_spread)},
      {"observer_speed_spread", number(o.exploration.speed_spread)},
      {"observer_rt_median", number(o.rt_median_s)},
      {"observer_rt_log_sd", number(o.rt_log_sd)},
      {"observer_match_tolerance", number(o.match_tolerance)},
      {"observer_answers", answers}};
}

bool IsObserverColumn(const std::string& column) {
  return column.starts_with("observer_");
}

}  // namespace burrlab::runner
