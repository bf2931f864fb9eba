// How likely a model makes a published group result: a paper reports the mean
// score of n subjects and its SEM, each rounded (dissertation §13.5: "9.3 +-
// 0.4" of 12 from 20 subjects); a model of the subjects gives each one's
// score distribution over 0..trials. The probability that a study of n such
// subjects reports exactly those rounded numbers is the likelihood of the
// model given the publication, computed exactly: no normal approximation of
// the mean or of the sample variance (scores out of 12 from 20 subjects are
// far from normal near a ceiling), and the rounding is part of the data.
#ifndef BURRLAB_ANALYSIS_PUBLISHED_SCORES_H_
#define BURRLAB_ANALYSIS_PUBLISHED_SCORES_H_

#include <span>

#include "burrlab/base/result.h"

namespace burrlab::analysis {

// A published group result: mean correct answers of n subjects +- SEM (the
// sample SD, divisor n - 1, over sqrt(n)), each rounded to `decimals`.
struct PublishedScores {
  double mean = 0.0;
  double sem = 0.0;
  int n = 0;
  int decimals = 1;
};

// The probability that n subjects, each scoring independently k (0 <= k <
// score_probabilities.size()) with probability score_probabilities[k],
// give a mean in [mean - h, mean + h] and an SEM in [sem - h, sem + h], h =
// 0.5 x 10^-decimals (both ends included: a value on a rounding boundary
// could have been reported either way). Exact: a dynamic programme over the
// sum and the sum of squares of the scores. An error names a bad argument:
// n in [2, 1000], decimals in [0, 6], at most 1000 possible scores,
// probabilities >= 0 summing to 1 (within 1e-9).
Result<double> PublishedScoresProbability(
    std::span<const double> score_probabilities,
    const PublishedScores& published);

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_PUBLISHED_SCORES_H_
