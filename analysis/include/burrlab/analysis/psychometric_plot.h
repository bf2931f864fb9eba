// The figure of a psychometric fit: the data as markers whose area grows
// with the number of trials, each with the 95 % Wilson score interval of its
// proportion as an error bar (Wilson 1927; no distribution beyond the normal
// quantile, and unlike the Wald interval it stays in [0, 1] and keeps its
// coverage at the few trials per level of a staircase); the fitted psi; the
// guess rate gamma as a labelled horizontal line when gamma > 0; each
// threshold as a labelled vertical line with its 95 % BCa interval
// (percentile where BCa is unavailable) as a horizontal bar at the height psi
// reaches there.
#ifndef BURRLAB_ANALYSIS_PSYCHOMETRIC_PLOT_H_
#define BURRLAB_ANALYSIS_PSYCHOMETRIC_PLOT_H_

#include <span>
#include <string>
#include <vector>

#include "burrlab/analysis/plot.h"
#include "burrlab/analysis/psychometric.h"

namespace burrlab::analysis {

// `x_label` names the stimulus axis (with its unit).
LinePlot MakePsychometricPlot(std::span<const DataBlock> data,
                              const PsychometricAnalysis& analysis,
                              const std::string& x_label);

// Several conditions' fits in one figure: each condition's data (with
// Wilson intervals), fitted psi and threshold intervals in its own colour,
// labelled with its name; chance once.
LinePlot MakeConditionsPlot(std::span<const std::vector<DataBlock>> data,
                            std::span<const PsychometricAnalysis> analyses,
                            std::span<const std::string> names,
                            const std::string& x_label);

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_PSYCHOMETRIC_PLOT_H_
