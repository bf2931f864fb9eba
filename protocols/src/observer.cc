// The simulated observer's decision rules.
#include "burrlab/protocols/observer.h"

#include <fmt/format.h>

#include <boost/random/normal_distribution.hpp>
#include <boost/random/uniform_01.hpp>
#include <boost/random/uniform_int_distribution.hpp>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "burrlab/base/spelling.h"
#include "burrlab/protocols/streams.h"

namespace burrlab::protocols {
namespace {

// +1, -1 or 0.
int Sign(double v) { return (v > 0.0) - (v < 0.0); }

// A cue per interval, each finite and > 0.
Status CheckCues(const TrialSpec& trial, const TrialCues& cues) {
  if (cues.cues.size() != trial.intervals.size()) {
    return Error{fmt::format("observer: trial {} has {} intervals but {} cues",
                             trial.trial_index, trial.intervals.size(),
                             cues.cues.size())};
  }
  for (double c : cues.cues) {
    if (!(std::isfinite(c) && c > 0.0)) {
      return Error{fmt::format("observer: trial {}: a cue must be > 0, got {}",
                               trial.trial_index, c)};
    }
  }
  return {};
}

// Parses a finite number or returns an error naming the key.
Result<double> ParseNumber(std::string_view key, std::string_view text) {
  std::string s(text);
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(v)) {
    return Error{
        fmt::format("observer: {} must be a number, got \"{}\"", key, text)};
  }
  return v;
}

// ln of the normal density N(x; mean, variance).
double LogNormalDensity(double x, double mean, double variance) {
  const double d = x - mean;
  return -0.5 * std::log(2.0 * std::numbers::pi * variance) -
         d * d / (2.0 * variance);
}

// ln(e^a + e^b) without overflow.
double LogSumExp(double a, double b) {
  const double hi = std::max(a, b);
  return hi + std::log1p(std::exp(std::min(a, b) - hi));
}

}  // namespace

std::string_view SameDifferentRuleName(SameDifferentRule rule) {
  return kSameDifferentRuleNames[static_cast<int>(rule)];
}

Result<SameDifferentRule> ParseSameDifferentRule(std::string_view name) {
  for (int r = 0; r < 3; ++r) {
    if (name == kSameDifferentRuleNames[r])
      return static_cast<SameDifferentRule>(r);
  }
  return Error{fmt::format(
      "observer: rule must be fixed, differencing or likelihood, got \"{}\"",
      name)};
}

FeltMaterial FeltMaterialOf(std::span<const double> cues) {
  FeltMaterial m;
  if (cues.empty()) return m;
  double sum = 0.0;
  for (double c : cues) sum += std::log(c);
  m.mean_ln_cue = sum / static_cast<double>(cues.size());
  if (cues.size() > 1) {
    double ss = 0.0;
    for (double c : cues) {
      const double d = std::log(c) - m.mean_ln_cue;
      ss += d * d;
    }
    m.var_ln_cue = ss / static_cast<double>(cues.size() - 1);
  }
  return m;
}

double SameDifferentLogOdds(SameDifferentRule rule, double psi1, double psi2,
                            const FeltMaterial& a, const FeltMaterial& b,
                            double sigma) {
  const double va = a.var_ln_cue + sigma * sigma;
  const double vb = b.var_ln_cue + sigma * sigma;
  if (rule == SameDifferentRule::kDifferencing) {
    // The halves' ln 0.5 cancel between the two mixtures.
    const double d = psi1 - psi2;
    const double delta = a.mean_ln_cue - b.mean_ln_cue;
    const double same = LogSumExp(LogNormalDensity(d, 0.0, 2.0 * va),
                                  LogNormalDensity(d, 0.0, 2.0 * vb));
    const double different = LogSumExp(LogNormalDensity(d, delta, va + vb),
                                       LogNormalDensity(d, -delta, va + vb));
    return different - same;
  }
  const double a1 = LogNormalDensity(psi1, a.mean_ln_cue, va);
  const double a2 = LogNormalDensity(psi2, a.mean_ln_cue, va);
  const double b1 = LogNormalDensity(psi1, b.mean_ln_cue, vb);
  const double b2 = LogNormalDensity(psi2, b.mean_ln_cue, vb);
  return LogSumExp(a1 + b2, b1 + a2) - LogSumExp(a1 + a2, b1 + b2);
}

Status ObserverParams::Validate() const {
  auto positive = [](std::string_view name, double v, double max) -> Status {
    if (!(std::isfinite(v) && v > 0.0 && v <= max)) {
      return Error{
          fmt::format("observer: {} must be in (0, {}], got {}", name, max, v)};
    }
    return {};
  };
  if (Status s =
          positive("weber_stiffness", weber_stiffness, kMaxWeberFraction);
      !s.ok()) {
    return s;
  }
  if (Status s = positive("weber_removal", weber_removal, kMaxWeberFraction);
      !s.ok()) {
    return s;
  }
  if (!(lapse >= 0.0 && lapse < 0.5)) {
    return Error{
        fmt::format("observer: lapse must be in [0, 0.5), got {}", lapse)};
  }
  if (!(bias >= -kMaxBias && bias <= kMaxBias)) {
    return Error{fmt::format("observer: bias must be in [-{}, {}], got {}",
                             kMaxBias, kMaxBias, bias)};
  }
  if (!(std::isfinite(criterion) && criterion >= 0.0)) {
    return Error{fmt::format("observer: criterion must be 0 or more, got {}",
                             criterion)};
  }
  if (Status s = positive("rt_median_s", rt_median_s, 60.0); !s.ok()) return s;
  if (!(std::isfinite(rt_log_sd) && rt_log_sd >= 0.0 && rt_log_sd <= 2.0)) {
    return Error{fmt::format("observer: rt_log_sd must be in [0, 2], got {}",
                             rt_log_sd)};
  }
  if (Status s = positive("match_tolerance", match_tolerance, 10.0); !s.ok()) {
    return s;
  }
  for (const auto& [name, factor] :
       {std::pair{"force_factor", exploration.force_factor},
        std::pair{"speed_factor", exploration.speed_factor}}) {
    if (!(factor >= 1.0 / kMaxExplorationFactor &&
          factor <= kMaxExplorationFactor)) {
      return Error{fmt::format("observer: {} must be in [{}, {}], got {}", name,
                               1.0 / kMaxExplorationFactor,
                               kMaxExplorationFactor, factor)};
    }
  }
  for (const auto& [name, spread] :
       {std::pair{"force_spread", exploration.force_spread},
        std::pair{"speed_spread", exploration.speed_spread},
        std::pair{"subject_force_spread", exploration.subject_force_spread},
        std::pair{"subject_speed_spread", exploration.subject_speed_spread}}) {
    if (!(spread >= 0.0 && spread <= 1.0)) {
      return Error{
          fmt::format("observer: {} must be in [0, 1], got {}", name, spread)};
    }
  }
  return {};
}

stimuli::IntervalOptions ExploredInterval(
    const stimuli::IntervalOptions& nominal, const Exploration& e,
    boost::random::mt19937& stream) {
  if (!e.Varies()) return nominal;
  double force = e.force_factor, speed = e.speed_factor;
  if (e.force_spread > 0.0 || e.speed_spread > 0.0) {
    boost::random::normal_distribution<double> unit(0.0, 1.0);
    const double z_force = unit(stream);
    const double z_speed = unit(stream);
    force *= std::exp(e.force_spread * z_force);
    speed *= std::exp(e.speed_spread * z_speed);
  }
  stimuli::IntervalOptions o = nominal;
  constexpr double kMaxForceN = 20.0;  // IntervalOptions::Validate's bound
  o.probe_force_n =
      std::min({nominal.probe_force_n * force, kMaxForceN,
                stimuli::MaxProbeForceN(o.material, o.radius_mm, o.voxel_mm)});
  o.drill_force_n = std::min(nominal.drill_force_n * force, kMaxForceN);
  o.press_period_s = std::clamp(nominal.press_period_s / speed,
                                std::min(0.1, o.duration_s), o.duration_s);
  return o;
}

Result<const ProtocolMaterial*> ReferenceStandIn(const Protocol& protocol,
                                                 const Block& block) {
  const std::string& id = block.reference.matching_material == MaterialLabel::kA
                              ? block.material_a
                              : block.material_b;
  const ProtocolMaterial* m = protocol.FindMaterial(id);
  if (m == nullptr) return Error{"reference stand-in material is missing"};
  return m;
}

double ReferenceStandInDuration(const TrialSpec& trial) {
  return trial.intervals.size() > 1 ? trial.intervals[1].duration_s : 10.0;
}

SubjectDraws DrawSubject(std::uint64_t seed, int subject, bool explores) {
  boost::random::mt19937 population = StreamFor(
      seed, StreamPurpose::kPopulation, static_cast<std::uint64_t>(subject));
  boost::random::normal_distribution<double> unit(0.0, 1.0);
  SubjectDraws d;
  d.explores = explores;
  d.z = unit(population);
  if (explores) {
    d.z_force = unit(population);
    d.z_speed = unit(population);
  }
  return d;
}

ObserverParams ApplySubjectDraws(const ObserverParams& typical,
                                 WeberSpread spread, const SubjectDraws& d) {
  ObserverParams params = typical;
  const Exploration& e = typical.exploration;
  // A draw beyond the largest Weber fraction is held there (an observer at
  // chance stays at chance).
  params.weber_stiffness =
      std::min(kMaxWeberFraction,
               params.weber_stiffness * std::exp(d.z * spread.stiffness));
  params.weber_removal = std::min(
      kMaxWeberFraction, params.weber_removal * std::exp(d.z * spread.removal));
  if (d.explores) {
    auto held = [](double factor) {
      return std::clamp(factor, 1.0 / kMaxExplorationFactor,
                        kMaxExplorationFactor);
    };
    params.exploration.force_factor =
        held(e.force_factor * std::exp(d.z_force * e.subject_force_spread));
    params.exploration.speed_factor =
        held(e.speed_factor * std::exp(d.z_speed * e.subject_speed_spread));
  }
  return params;
}

ObserverParams DrawSubjectObserver(const ObserverParams& typical,
                                   WeberSpread spread, std::uint64_t seed,
                                   int subject) {
  const Exploration& e = typical.exploration;
  const bool explores =
      e.subject_force_spread > 0.0 || e.subject_speed_spread > 0.0;
  if (spread.stiffness > 0.0 || spread.removal > 0.0 || explores) {
    return ApplySubjectDraws(typical, spread,
                             DrawSubject(seed, subject, explores));
  }
  return typical;
}

Result<TrialCues> RememberedStandards::CuesFor(
    const TrialSpec& trial, std::span<const double> cues,
    const std::function<Result<double>()>& feel) {
  TrialCues trial_cues;
  trial_cues.cues = cues;
  if (trial.intervals.size() == 1) {
    auto it = by_block_.find(trial.block_index);
    if (it == by_block_.end()) {
      Result<double> standard = feel();
      if (!standard.ok()) return standard.error();
      it = by_block_.emplace(trial.block_index, standard.value()).first;
    }
    trial_cues.standard_cue = it->second;
  }
  return trial_cues;
}

ObserverParams ObserverParamsFrom(const ObserverDefaults& defaults) {
  ObserverParams p;
  p.weber_stiffness = defaults.weber_stiffness;
  p.weber_removal = defaults.weber_removal;
  p.lapse = defaults.lapse;
  p.criterion = defaults.criterion;
  p.rule = defaults.rule;
  p.bias = defaults.bias;
  p.exploration.force_spread = defaults.exploration.force;
  p.exploration.speed_spread = defaults.exploration.speed;
  p.exploration.subject_force_spread = defaults.exploration.subject_force;
  p.exploration.subject_speed_spread = defaults.exploration.subject_speed;
  return p;
}

Result<ObserverParams> ParseObserverSpec(std::string_view spec,
                                         ObserverParams base) {
  constexpr std::string_view kHead = "simulated";
  if (!spec.starts_with(kHead) ||
      (spec.size() > kHead.size() && spec[kHead.size()] != ':')) {
    return Error{fmt::format(
        "--observer must be 'simulated' or 'simulated:key=value,...', got "
        "\"{}\"",
        spec)};
  }
  std::string_view rest =
      spec.size() > kHead.size() ? spec.substr(kHead.size() + 1) : "";
  constexpr std::string_view kKeys[] = {"weber",
                                        "weber_stiffness",
                                        "weber_removal",
                                        "lapse",
                                        "criterion",
                                        "bias",
                                        "rt_median_s",
                                        "rule",
                                        "always",
                                        "exploration",
                                        "force_spread",
                                        "speed_spread",
                                        "subject_force_spread",
                                        "subject_speed_spread"};
  constexpr std::string_view kKeyList =
      "weber, weber_stiffness, weber_removal, lapse, criterion, bias, "
      "rt_median_s, rule, always, exploration, force_spread, speed_spread, "
      "subject_force_spread, subject_speed_spread";
  while (!rest.empty()) {
    const std::size_t comma = rest.find(',');
    std::string_view item = rest.substr(0, comma);
    rest = comma == std::string_view::npos ? "" : rest.substr(comma + 1);
    const std::size_t eq = item.find('=');
    if (eq == std::string_view::npos) {
      return Error{fmt::format("observer: \"{}\" is not key=value (keys: {})",
                               item, kKeyList)};
    }
    const std::string_view key = item.substr(0, eq);
    if (key == "rule") {
      const std::string_view name = item.substr(eq + 1);
      Result<SameDifferentRule> rule = ParseSameDifferentRule(name);
      if (!rule.ok()) return rule.error();
      base.rule = *rule;
      continue;
    }
    if (key == "exploration") {
      const std::string_view name = item.substr(eq + 1);
      if (name != "fixed" && name != "varied") {
        return Error{fmt::format(
            "observer: exploration must be fixed or varied, got \"{}\"", name)};
      }
      const ExplorationSpreads spreads =
          name == "varied" ? kVariedExploration : ExplorationSpreads{};
      base.exploration.force_spread = spreads.force;
      base.exploration.speed_spread = spreads.speed;
      base.exploration.subject_force_spread = spreads.subject_force;
      base.exploration.subject_speed_spread = spreads.subject_speed;
      continue;
    }
    if (key == "always") {
      const std::string_view rule = item.substr(eq + 1);
      if (rule == "correct") {
        base.answers = AnswerRule::kAlwaysCorrect;
      } else if (rule == "wrong") {
        base.answers = AnswerRule::kAlwaysWrong;
      } else {
        return Error{fmt::format(
            "observer: always must be correct or wrong, got \"{}\"", rule)};
      }
      continue;
    }
    Result<double> value = ParseNumber(key, item.substr(eq + 1));
    if (!value.ok()) return value.error();
    if (key == "weber") {
      base.weber_stiffness = base.weber_removal = value.value();
    } else if (key == "weber_stiffness") {
      base.weber_stiffness = value.value();
    } else if (key == "weber_removal") {
      base.weber_removal = value.value();
    } else if (key == "lapse") {
      base.lapse = value.value();
    } else if (key == "criterion") {
      base.criterion = value.value();
    } else if (key == "bias") {
      base.bias = value.value();
    } else if (key == "rt_median_s") {
      base.rt_median_s = value.value();
    } else if (key == "force_spread") {
      base.exploration.force_spread = value.value();
    } else if (key == "speed_spread") {
      base.exploration.speed_spread = value.value();
    } else if (key == "subject_force_spread") {
      base.exploration.subject_force_spread = value.value();
    } else if (key == "subject_speed_spread") {
      base.exploration.subject_speed_spread = value.value();
    } else {
      const std::string_view hint = DidYouMean(key, kKeys);
      return Error{fmt::format(
          "observer: unknown key \"{}\"{} (keys: {})", key,
          hint.empty() ? "" : fmt::format(" (did you mean \"{}\"?)", hint),
          kKeyList)};
    }
  }
  if (Status s = base.Validate(); !s.ok()) return s.error();
  return base;
}

double SimulatedObserver::Sigma(Task task) const {
  return task == Task::kProbe ? params_.weber_stiffness : params_.weber_removal;
}

double SimulatedObserver::ResponseTime(boost::random::mt19937& rng) const {
  boost::random::normal_distribution<double> z(0.0, 1.0);
  return params_.rt_median_s * std::exp(params_.rt_log_sd * z(rng));
}

SimulatedObserver::Noise SimulatedObserver::DrawNoise(
    const TrialSpec& trial, boost::random::mt19937& rng) const {
  boost::random::uniform_01<double> u;
  boost::random::normal_distribution<double> z(0.0, 1.0);
  Noise noise;
  noise.lapse = u(rng) < params_.lapse;
  for (std::size_t i = 0; i < trial.intervals.size(); ++i) {
    const double draw = z(rng);
    if (i < noise.z.size()) noise.z[i] = draw;
  }
  if (noise.lapse) {
    boost::random::uniform_int_distribution<int> pick(
        0, static_cast<int>(trial.response_options.size()) - 1);
    noise.lapse_answer = pick(rng);
  }
  noise.rt_z = z(rng);
  return noise;
}

Result<Response> SimulatedObserver::Decide(const TrialSpec& trial,
                                           const TrialCues& cues,
                                           boost::random::mt19937& rng) const {
  if (Status st = CheckCues(trial, cues); !st.ok()) return st.error();
  return DecideWith(trial, cues, DrawNoise(trial, rng));
}

Result<Response> SimulatedObserver::DecideWith(const TrialSpec& trial,
                                               const TrialCues& cues,
                                               const Noise& noise) const {
  if (Status st = CheckCues(trial, cues); !st.ok()) return st.error();
  const double sigma = Sigma(trial.task);
  std::array<double, 4> psi{};
  for (std::size_t i = 0; i < cues.cues.size() && i < psi.size(); ++i) {
    psi[i] = std::log(cues.cues[i]) + sigma * noise.z[i];
  }

  std::string answer;
  const std::size_t n = cues.cues.size();
  const double k = params_.criterion * sigma * std::sqrt(2.0);
  switch (trial.method) {
    case Method::kSameDifferent:
    case Method::kLimits:
      if (n != 2) return Error{"observer: expected two intervals"};
      {
        bool different = std::abs(psi[0] - psi[1]) > k;
        if (trial.method == Method::kSameDifferent &&
            params_.rule != SameDifferentRule::kFixed) {
          if (!cues.materials.has_value()) {
            return Error{fmt::format(
                "observer: the {} rule needs the block's two materials as "
                "the observer felt them",
                SameDifferentRuleName(params_.rule))};
          }
          different = SameDifferentLogOdds(
                          params_.rule, psi[0], psi[1], (*cues.materials)[0],
                          (*cues.materials)[1], sigma) > params_.bias;
        }
        if (trial.method == Method::kSameDifferent) {
          answer = different ? "different" : "same";
        } else {
          answer = different ? "yes" : "no";
        }
      }
      break;
    case Method::kTwoInterval:
      if (n == 3) {  // reference design: the comparison closer to the reference
        answer = std::to_string(
            std::abs(psi[1] - psi[0]) <= std::abs(psi[2] - psi[0]) ? 2 : 3);
        break;
      }
      [[fallthrough]];
    default:
      if (trial.method == Method::kAdjustment) {
        return Error{
            "observer: adjustment trials go step by step (AdjustStep)"};
      }
      if (n == 2) {
        // The question asks which interval is higher on the axis (for
        // material designs: which holds the comparison). `rise` is +1 when
        // the cue grows with the level, -1 when it falls (the observer knows
        // what "more" feels like); the interval whose percept lies further
        // that way is chosen.
        auto level_of = [](const PlannedInterval& i) {
          return i.level.value_or(i.role == "comparison" ? 1.0 : 0.0);
        };
        const double dl =
            level_of(trial.intervals[1]) - level_of(trial.intervals[0]);
        int rise = Sign((std::log(cues.cues[1]) - std::log(cues.cues[0])) * dl);
        if (rise == 0) rise = 1;
        answer = std::to_string(rise * (psi[1] - psi[0]) > 0.0 ? 2 : 1);
      } else if (n == 1) {
        if (!cues.standard_cue.has_value() || !(*cues.standard_cue > 0.0)) {
          return Error{"observer: a yes/no trial needs the standard's cue"};
        }
        const double level = trial.intervals[0].level.value_or(0.0);
        const double standard = trial.standard_level.value_or(0.0);
        const double dl = level - standard;
        int direction =
            Sign((std::log(cues.cues[0]) - std::log(*cues.standard_cue)) * dl);
        if (direction == 0) direction = 1;
        answer = direction * (psi[0] - std::log(*cues.standard_cue)) > 0.0
                     ? "yes"
                     : "no";
      } else {
        return Error{
            fmt::format("observer: cannot decide a trial with {} "
                        "intervals",
                        n)};
      }
      break;
  }
  if (noise.lapse) {
    answer =
        trial.response_options[static_cast<std::size_t>(noise.lapse_answer)];
  }
  if (params_.answers != AnswerRule::kPercepts) {
    // The fixed answer, as a script's "1" or "0" stands for it.
    Result<Response> fixed = ScriptedResponse(
        trial, params_.answers == AnswerRule::kAlwaysCorrect ? "1" : "0");
    if (fixed.ok()) answer = fixed->answer;
  }
  Response r;
  r.answer = answer;
  r.response_time_s =
      params_.rt_median_s * std::exp(params_.rt_log_sd * noise.rt_z);
  return r;
}

char SimulatedObserver::AdjustStep(Task task, double standard_cue,
                                   double comparison_cue, int direction,
                                   boost::random::mt19937& rng) const {
  if (params_.answers == AnswerRule::kAlwaysCorrect) return '+';
  if (params_.answers == AnswerRule::kAlwaysWrong) return '-';
  const double sigma = Sigma(task);
  boost::random::normal_distribution<double> z(0.0, 1.0);
  const double psi_s = std::log(standard_cue) + sigma * z(rng);
  const double psi_c = std::log(comparison_cue) + sigma * z(rng);
  const double diff = psi_c - psi_s;
  if (std::abs(diff) < params_.match_tolerance * sigma) return '=';
  // The comparison feels "more": move the level so the cue shrinks.
  const int sign = direction >= 0 ? 1 : -1;
  return diff * sign > 0.0 ? '-' : '+';
}

Result<Response> SimulatedObserver::Adjust(const TrialSpec& trial,
                                           double standard_cue,
                                           double start_cue, int max_steps,
                                           boost::random::mt19937& rng,
                                           const AdjustedCue& cue_at) const {
  const double start_level = trial.level.value_or(0.0);
  const double standard_level = trial.standard_level.value_or(0.0);
  int direction = 1;
  if (start_level != standard_level && start_cue != standard_cue) {
    direction =
        ((start_cue > standard_cue) == (start_level > standard_level)) ? 1 : -1;
  }
  std::string path;
  double cue = start_cue;
  double rt = 0.0;
  for (int step = 0; step < max_steps; ++step) {
    const char c = AdjustStep(trial.task, standard_cue, cue, direction, rng);
    rt += ResponseTime(rng);
    if (c == '=') break;
    Result<std::optional<double>> felt = cue_at(path + c);
    if (!felt.ok()) return felt.error();
    if (!felt->has_value()) break;  // a step beyond the limit ends it
    path += c;
    cue = **felt;
  }
  return Response{path + "=", rt};
}

}  // namespace burrlab::protocols
