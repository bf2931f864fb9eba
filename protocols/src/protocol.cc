// The protocol model's small functions: names, parameters, axes, block order
// and the diagnostic format (the parser is in protocol_parse.cc).
#include "burrlab/protocols/protocol.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "burrlab/base/printable.h"

namespace burrlab::protocols {

namespace {

// The line of `text` starting at byte `start`, without its line break.
std::string_view LineAt(std::string_view text, std::size_t start) {
  std::size_t end = text.find('\n', start);
  if (end == std::string_view::npos) end = text.size();
  std::string_view line = text.substr(start, end - start);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  return line;
}

// The diagnostic's first line, then (with a location) `source` quoted with a
// caret under the column.
std::string Format(std::string_view path, const Diagnostic& diagnostic,
                   std::string_view source) {
  const std::string message = PrintableText(diagnostic.message);
  const std::string_view kind =
      diagnostic.severity == Severity::kNote ? "note" : "error";
  if (diagnostic.where.line <= 0) {
    return fmt::format("{}: {}: {}\n", path, kind, message);
  }
  return fmt::format("{}:{}:{}: {}: {}\n{}\n", path, diagnostic.where.line,
                     diagnostic.where.column, kind, message,
                     QuoteLineWithCaret(source, diagnostic.where.column));
}

}  // namespace

std::string FormatDiagnostic(std::string_view path, std::string_view text,
                             const Diagnostic& diagnostic) {
  // The source line (1-based).
  std::size_t start = 0;
  for (int line = 1; line < diagnostic.where.line && start < text.size();
       ++line) {
    const std::size_t next = text.find('\n', start);
    if (next == std::string_view::npos) {
      start = text.size();
      break;
    }
    start = next + 1;
  }
  return Format(path, diagnostic, LineAt(text, start));
}

std::string FormatDiagnostics(std::string_view path, std::string_view text,
                              std::span<const Diagnostic> diagnostics) {
  const std::size_t shown =
      std::min(diagnostics.size(), kMaxPrintedDiagnostics);
  // Where each line starts, found once (not once per diagnostic), and only as
  // far as the last line shown.
  int last_line = 0;
  for (std::size_t i = 0; i < shown; ++i) {
    last_line = std::max(last_line, diagnostics[i].where.line);
  }
  std::vector<std::size_t> line_starts = {0};
  for (std::size_t i = 0;
       static_cast<int>(line_starts.size()) < last_line && i < text.size();
       ++i) {
    if (text[i] == '\n') line_starts.push_back(i + 1);
  }
  std::string out;
  for (std::size_t i = 0; i < shown; ++i) {
    const Diagnostic& d = diagnostics[i];
    const std::size_t line =
        static_cast<std::size_t>(std::max(d.where.line, 1));
    const std::size_t start =
        line <= line_starts.size() ? line_starts[line - 1] : text.size();
    out += Format(path, d, LineAt(text, start));
  }
  if (diagnostics.size() > shown) {
    const std::size_t more = diagnostics.size() - shown;
    out += fmt::format(
        "{}: ... and {} more {}{}\n", path, more,
        diagnostics[shown].severity == Severity::kNote ? "note" : "error",
        more == 1 ? "" : "s");
  }
  return out;
}

std::string_view MaterialParameterName(MaterialParameter parameter) {
  switch (parameter) {
    case MaterialParameter::kCE:
      return "c_e";
    case MaterialParameter::kAlpha:
      return "alpha";
    case MaterialParameter::kCMu:
      return "c_mu";
    case MaterialParameter::kMu:
      return "mu";
    case MaterialParameter::kCI:
      return "c_i";
  }
  return "?";
}

double GetParameter(const sim::Material& material,
                    MaterialParameter parameter) {
  switch (parameter) {
    case MaterialParameter::kCE:
      return material.c_e_n_per_mm2;
    case MaterialParameter::kAlpha:
      return material.alpha_per_s;
    case MaterialParameter::kCMu:
      return material.c_mu_n_per_mm2;
    case MaterialParameter::kMu:
      return material.mu;
    case MaterialParameter::kCI:
      return material.c_i_n_s_per_mm3;
  }
  return 0.0;
}

sim::Material WithParameter(sim::Material material, MaterialParameter parameter,
                            double value) {
  switch (parameter) {
    case MaterialParameter::kCE:
      material.c_e_n_per_mm2 = value;
      break;
    case MaterialParameter::kAlpha:
      material.alpha_per_s = value;
      break;
    case MaterialParameter::kCMu:
      material.c_mu_n_per_mm2 = value;
      break;
    case MaterialParameter::kMu:
      material.mu = value;
      break;
    case MaterialParameter::kCI:
      material.c_i_n_s_per_mm3 = value;
      break;
  }
  return material;
}

std::string_view AxisKindName(AxisKind kind) {
  switch (kind) {
    case AxisKind::kRatio:
      return "ratio";
    case AxisKind::kIncrement:
      return "increment";
    case AxisKind::kValue:
      return "value";
    case AxisKind::kLogInterpolation:
      return "log_interpolation";
  }
  return "?";
}

std::string AxisUnit(const Axis& axis) {
  switch (axis.kind) {
    case AxisKind::kRatio:
      return "ratio";
    case AxisKind::kIncrement:
      return "fraction";
    case AxisKind::kLogInterpolation:
      return "t";
    case AxisKind::kValue:
      switch (axis.parameter) {
        case MaterialParameter::kCE:
        case MaterialParameter::kCMu:
          return "N/mm^2";
        case MaterialParameter::kAlpha:
          return "1/s";
        case MaterialParameter::kMu:
          return "1";
        case MaterialParameter::kCI:
          return "N s/mm^3";
      }
  }
  return "";
}

std::string_view MethodName(Method method) {
  switch (method) {
    case Method::kSameDifferent:
      return "same_different";
    case Method::kTwoInterval:
      return "two_interval";
    case Method::kConstantStimuli:
      return "constant_stimuli";
    case Method::kLimits:
      return "limits";
    case Method::kAdjustment:
      return "adjustment";
    case Method::kStaircase:
      return "staircase";
    case Method::kQuest:
      return "quest";
  }
  return "?";
}

std::string NoFeedbackReason(const Block& block) {
  switch (block.method) {
    case Method::kLimits:
      return "method limits has no correct answer (the subject says whether "
             "the comparison felt different)";
    case Method::kAdjustment:
      return "method adjustment has no correct answer (the level the subject "
             "sets is recorded)";
    case Method::kStaircase:
    case Method::kQuest:
      if (block.adaptive_response == AdaptiveResponse::kYesNo) {
        return fmt::format(
            "a yes/no {} block counts every \"yes\" as correct, so feedback "
            "would only repeat the answer",
            MethodName(block.method));
      }
      return {};
    default:
      return {};
  }
}

const ProtocolMaterial* Protocol::FindMaterial(std::string_view id) const {
  for (const ProtocolMaterial& m : materials) {
    if (m.id == id) return &m;
  }
  return nullptr;
}

const Axis* Protocol::FindAxis(std::string_view id) const {
  for (const Axis& a : axes) {
    if (a.id == id) return &a;
  }
  return nullptr;
}

Result<stimuli::MaterialSet> MaterialAtLevel(const Protocol& protocol,
                                             const Axis& axis, double level) {
  auto domain_error = [&](std::string_view rule) -> Error {
    return Error{
        fmt::format("axis \"{}\" ({}): level {} is outside its "
                    "domain ({})",
                    axis.id, AxisKindName(axis.kind), level, rule)};
  };
  if (!std::isfinite(level)) return domain_error("a finite number");
  stimuli::MaterialSet set;
  if (axis.kind == AxisKind::kLogInterpolation) {
    if (level < 0.0 || level > 1.0) return domain_error("0 to 1");
    const ProtocolMaterial* from = protocol.FindMaterial(axis.from);
    const ProtocolMaterial* to = protocol.FindMaterial(axis.to);
    if (from == nullptr || to == nullptr) {
      return Error{fmt::format("axis \"{}\": unknown material \"{}\"", axis.id,
                               from == nullptr ? axis.from : axis.to)};
    }
    set.material = from->set.material;
    for (MaterialParameter p :
         {MaterialParameter::kCE, MaterialParameter::kAlpha,
          MaterialParameter::kCMu, MaterialParameter::kMu,
          MaterialParameter::kCI}) {
      const double a = GetParameter(from->set.material, p);
      const double b = GetParameter(to->set.material, p);
      // Geometric interpolation: equal steps in level are equal ratios.
      const double v =
          a > 0.0 && b > 0.0
              ? std::exp((1.0 - level) * std::log(a) + level * std::log(b))
              : (1.0 - level) * a + level * b;
      set.material = WithParameter(set.material, p, v);
    }
    set.display_name =
        fmt::format("{} between {} and {} at t = {}", axis.id,
                    from->set.display_name, to->set.display_name, level);
  } else {
    const ProtocolMaterial* reference = protocol.FindMaterial(axis.reference);
    if (reference == nullptr) {
      return Error{fmt::format("axis \"{}\": unknown material \"{}\"", axis.id,
                               axis.reference)};
    }
    const double base = GetParameter(reference->set.material, axis.parameter);
    double value = 0.0;
    switch (axis.kind) {
      case AxisKind::kRatio:
        if (level <= 0.0) return domain_error("greater than 0");
        value = base * level;
        break;
      case AxisKind::kIncrement:
        if (level <= -1.0) return domain_error("greater than -1");
        value = base * (1.0 + level);
        break;
      case AxisKind::kValue:
        if (level <= 0.0) return domain_error("greater than 0");
        value = level;
        break;
      case AxisKind::kLogInterpolation:
        break;
    }
    set.material =
        WithParameter(reference->set.material, axis.parameter, value);
    set.display_name = fmt::format("{} with {} = {} ({} {} on axis {})",
                                   reference->set.display_name,
                                   MaterialParameterName(axis.parameter), value,
                                   AxisKindName(axis.kind), level, axis.id);
  }
  // Within what [materials] accepts: an overflowing level (1e308 x c_e) or
  // one far beyond the declared materials is refused here, not mid-session.
  for (MaterialParameter p : {MaterialParameter::kCE, MaterialParameter::kAlpha,
                              MaterialParameter::kCMu, MaterialParameter::kMu,
                              MaterialParameter::kCI}) {
    const double v = GetParameter(set.material, p);
    const bool positive = p == MaterialParameter::kCE;
    if (!(std::isfinite(v) && (positive ? v > 0.0 : v >= 0.0) &&
          v <= kMaxMaterialParameter)) {
      return Error{fmt::format(
          "axis \"{}\" ({}): level {} gives {} = {}, outside {}0, {}] (the "
          "range [materials] accepts)",
          axis.id, AxisKindName(axis.kind), level, MaterialParameterName(p), v,
          positive ? "(" : "[", kMaxMaterialParameter)};
    }
  }
  std::string name = fmt::format("{}@{:.8g}", axis.id, level);
  std::erase(name, '+');
  set.name = std::move(name);
  set.source = fmt::format("axis {} of the protocol", axis.id);
  return set;
}

std::pair<double, double> AxisDomain(const Protocol& protocol,
                                     const Axis& axis) {
  constexpr double kTiny = 1e-9;
  constexpr double kHuge = 1e9;
  if (axis.kind == AxisKind::kLogInterpolation) return {0.0, 1.0};
  double lo = axis.kind == AxisKind::kIncrement ? -1.0 + kTiny : kTiny;
  double hi = kHuge;
  const ProtocolMaterial* reference = protocol.FindMaterial(axis.reference);
  const double base =
      reference == nullptr
          ? 0.0
          : GetParameter(reference->set.material, axis.parameter);
  // The parameter at level L; the largest L keeping it within the cap is
  // found in closed form, then stepped down past any rounding.
  auto value = [&](double level) {
    switch (axis.kind) {
      case AxisKind::kRatio:
        return base * level;
      case AxisKind::kIncrement:
        return base * (1.0 + level);
      default:
        return level;
    }
  };
  if (axis.kind == AxisKind::kValue) {
    hi = kMaxMaterialParameter;
  } else if (base > 0.0) {
    hi = std::min(hi, axis.kind == AxisKind::kRatio
                          ? kMaxMaterialParameter / base
                          : kMaxMaterialParameter / base - 1.0);
  }
  while (value(hi) > kMaxMaterialParameter) hi = std::nextafter(hi, lo);
  return {lo, hi};
}

stimuli::IntervalOptions SimulatedIntervalOptions(const Protocol& protocol,
                                                  double radius_mm, Task task,
                                                  const sim::Material& material,
                                                  double duration_s) {
  stimuli::IntervalOptions o;
  o.material = material;
  o.task = task;
  o.duration_s = duration_s;
  // One press per second, or one press over a shorter interval.
  o.press_period_s = std::min(o.press_period_s, duration_s);
  o.radius_mm = radius_mm;
  o.probe_force_n = protocol.observer.probe_force_n;
  o.drill_force_n = protocol.observer.drill_force_n;
  o.trace_hz = protocol.trace_hz;
  return o;
}

std::vector<Diagnostic> CheckSimulatedIntervals(const Protocol& protocol,
                                                double radius_mm) {
  std::vector<Diagnostic> out;
  for (const Block& b : protocol.blocks) {
    double duration_s = 0.0;  // the shortest simulated interval
    for (double d : b.interval_s) {
      if (d > 0.0 && (duration_s == 0.0 || d < duration_s)) duration_s = d;
    }
    if (duration_s == 0.0) duration_s = 10.0;
    for (const ReachedStimulus& r : b.reach) {
      stimuli::IntervalOptions o = SimulatedIntervalOptions(
          protocol, radius_mm, b.task, r.set.material, duration_s);
      // What fails whatever the material (the radius) is said once.
      stimuli::IntervalOptions any = o;
      any.task = Task::kDrill;
      if (Status s = any.Validate(); !s.ok()) {
        return {{{}, s.error().message}};
      }
      if (Status s = o.Validate(); !s.ok()) {
        std::string message = s.error().message;
        if (message.starts_with("interval: ")) message.erase(0, 10);
        out.push_back(
            {r.where,
             b.task == Task::kProbe
                 ? fmt::format("{}: the simulated hand cannot probe it: {}; "
                               "lower [observer] probe_force_n or {}",
                               r.what, message,
                               r.level.has_value()
                                   ? "keep the levels where the material is "
                                     "stiffer"
                                   : "name a stiffer material")
                 : fmt::format("{}: {}", r.what, message)});
      }
    }
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const Diagnostic& a, const Diagnostic& b) {
                     return std::pair(a.where.line, a.where.column) <
                            std::pair(b.where.line, b.where.column);
                   });
  return out;
}

std::vector<int> BlockOrder(const Protocol& protocol, int subject_index) {
  const int n = static_cast<int>(protocol.blocks.size());
  std::vector<int> order(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) order[static_cast<std::size_t>(i)] = i;
  if (n < 2 || subject_index < 0) return order;
  switch (protocol.counterbalance) {
    case Counterbalance::kNone:
      break;
    case Counterbalance::kReverse:
      if (subject_index % 2 == 1) std::reverse(order.begin(), order.end());
      break;
    case Counterbalance::kLatinSquare: {
      // Williams design: first row 0, 1, n-1, 2, n-2, ...; row r adds r
      // (mod n). For even n every block precedes every other exactly once
      // over the n rows; for odd n the n mirrored rows follow (2n rows).
      std::vector<int> first;
      for (int k = 0, lo = 1, hi = n - 1; k < n; ++k) {
        if (k == 0) {
          first.push_back(0);
        } else if (k % 2 == 1) {
          first.push_back(lo++);
        } else {
          first.push_back(hi--);
        }
      }
      const int rows = n % 2 == 0 ? n : 2 * n;
      const int row = subject_index % rows;
      for (int k = 0; k < n; ++k) {
        const int value = (first[static_cast<std::size_t>(k)] + row % n) % n;
        order[static_cast<std::size_t>(row < n ? k : n - 1 - k)] = value;
      }
      break;
    }
  }
  return order;
}

}  // namespace burrlab::protocols
