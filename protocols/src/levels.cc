// Step scales and the rounding of presented levels; see levels.h.
#include "burrlab/protocols/levels.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <string>

namespace burrlab::protocols {
namespace {

// The double a decimal text reads as (strtod rounds correctly).
double ReadDecimal(const std::string& text) {
  return std::strtod(text.c_str(), nullptr) + 0.0;  // -0 becomes 0
}

// `value` rounded to a multiple of 10^place: printed with that many decimals
// (fmt rounds the exact binary value) and read back, so the result is the
// double nearest to the decimal, the one its shortest text reads back as.
double RoundToPlace(double value, int place) {
  if (!std::isfinite(value) || value == 0.0) return value;
  if (place >= 0) {
    const double scale = std::pow(10.0, place);
    return std::round(value / scale) * scale + 0.0;
  }
  return ReadDecimal(fmt::format("{:.{}f}", value, -place));
}

// Decimal place of the leading digit of `value` (> 0): 0.05 -> -2.
int LeadingPlace(double value) {
  return static_cast<int>(std::floor(std::log10(std::fabs(value))));
}

}  // namespace

std::string_view StepScaleName(StepScale scale) {
  switch (scale) {
    case StepScale::kLinear:
      return "linear";
    case StepScale::kLog10:
      return "log10";
    case StepScale::kDecibel:
      return "db";
  }
  return "?";
}

double ApplyStep(double level, double steps, StepScale scale) {
  switch (scale) {
    case StepScale::kLinear:
      return level + steps;
    case StepScale::kLog10:
      return level * std::pow(10.0, steps);
    case StepScale::kDecibel:
      return level * std::pow(10.0, steps / 20.0);
  }
  return level;
}

double ToScaleDomain(double level, StepScale scale) {
  switch (scale) {
    case StepScale::kLinear:
      return level;
    case StepScale::kLog10:
      return std::log10(level);
    case StepScale::kDecibel:
      return 20.0 * std::log10(level);
  }
  return level;
}

double FromScaleDomain(double value, StepScale scale) {
  switch (scale) {
    case StepScale::kLinear:
      return value;
    case StepScale::kLog10:
      return std::pow(10.0, value);
    case StepScale::kDecibel:
      return std::pow(10.0, value / 20.0);
  }
  return value;
}

double RoundSignificant(double value) {
  if (!std::isfinite(value) || value == 0.0) return value;
  return ReadDecimal(fmt::format("{:.{}e}", value, kLevelDigits - 1));
}

double RoundToStep(double value, double step) {
  if (!(step > 0.0) || !std::isfinite(step)) return value;
  return RoundToPlace(value, LeadingPlace(step) - (kLevelDigits - 1));
}

double StepResolution(double step) {
  return std::pow(10.0, LeadingPlace(step) - (kLevelDigits - 1));
}

double LevelAt(double anchor, double offset, double step, StepScale scale) {
  switch (scale) {
    case StepScale::kLinear:
      return RoundToStep(anchor + offset, step);
    case StepScale::kLog10:
    case StepScale::kDecibel:
      return RoundSignificant(ApplyStep(anchor, offset, scale));
  }
  return anchor;
}

}  // namespace burrlab::protocols
