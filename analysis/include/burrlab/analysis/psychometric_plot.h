// The figure of a psychometric fit: the data as markers whose area grows
// with the number of trials, the fitted psi, and each threshold with its
// 95 % BCa interval (percentile where BCa is unavailable) as a horizontal
// bar at the height psi reaches there.
#ifndef BURRLAB_ANALYSIS_PSYCHOMETRIC_PLOT_H_
#define BURRLAB_ANALYSIS_PSYCHOMETRIC_PLOT_H_

#include <span>
#include <string>

#include "burrlab/analysis/plot.h"
#include "burrlab/analysis/psychometric.h"

namespace burrlab::analysis {

// `x_label` names the stimulus axis (with its unit).
LinePlot MakePsychometricPlot(std::span<const DataBlock> data,
                              const PsychometricAnalysis& analysis,
                              const std::string& x_label);

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_PSYCHOMETRIC_PLOT_H_
