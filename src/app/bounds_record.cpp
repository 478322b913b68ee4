#include "app/bounds_record.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace fricrom::app {
namespace {

using json = nlohmann::json;

json Real(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json Vector(const Eigen::VectorXd& v) {
  json a = json::array();
  for (double x : v) a.push_back(Real(x));
  return a;
}

const json& Key(const json& j, const char* key) {
  if (!j.is_object() || !j.contains(key)) {
    throw std::runtime_error(std::string("bound record: missing key '") + key + "'");
  }
  return j.at(key);
}

double ReadReal(const json& j, const char* key) {
  const json& v = Key(j, key);
  if (v.is_null()) return std::numeric_limits<double>::quiet_NaN();
  if (!v.is_number()) {
    throw std::runtime_error(std::string("bound record: '") + key + "' is not a number");
  }
  return v.get<double>();
}

int ReadInt(const json& j, const char* key) {
  const json& v = Key(j, key);
  if (!v.is_number_integer()) {
    throw std::runtime_error(std::string("bound record: '") + key + "' is not an integer");
  }
  return v.get<int>();
}

Eigen::VectorXd ReadVector(const json& j, const char* key) {
  const json& a = Key(j, key);
  if (!a.is_array())
    throw std::runtime_error(std::string("bound record: '") + key + "' is not a list");
  Eigen::VectorXd v(static_cast<Eigen::Index>(a.size()));
  for (size_t i = 0; i < a.size(); ++i) {
    if (!a[i].is_null() && !a[i].is_number()) {
      throw std::runtime_error(std::string("bound record: '") + key + "' holds a non-number");
    }
    v[static_cast<Eigen::Index>(i)] =
        a[i].is_null() ? std::numeric_limits<double>::quiet_NaN() : a[i].get<double>();
  }
  return v;
}

json SolutionRecord(const BoundSolution& s) {
  json regimes = json::array();
  for (ContactRegime r : s.regimes) regimes.push_back(static_cast<int>(r));
  return {{"x", Vector(s.x)},
          {"alpha", Vector(s.alpha)},
          {"amplitude", Real(s.amplitude)},
          {"loss_factor", Real(s.loss_factor)},
          {"residual", Real(s.residual)},
          {"status", static_cast<int>(s.status)},
          {"stationary", s.stationary},
          {"message", s.message},
          {"iterations", s.iterations},
          {"seed", s.seed},
          {"regimes", regimes}};
}

BoundSolution SolutionFromRecord(const json& j) {
  BoundSolution s;
  s.x = ReadVector(j, "x");
  s.alpha = ReadVector(j, "alpha");
  s.amplitude = ReadReal(j, "amplitude");
  s.loss_factor = ReadReal(j, "loss_factor");
  s.residual = ReadReal(j, "residual");
  const int status = ReadInt(j, "status");
  if (status < 0 || status > static_cast<int>(BoundStatus::kFailed)) {
    throw std::runtime_error("bound record: unknown status " + std::to_string(status));
  }
  s.status = static_cast<BoundStatus>(status);
  if (!Key(j, "stationary").is_boolean()) {
    throw std::runtime_error("bound record: 'stationary' is not true or false");
  }
  s.stationary = j.at("stationary").get<bool>();
  if (!Key(j, "message").is_string()) throw std::runtime_error("bound record: bad 'message'");
  s.message = j.at("message").get<std::string>();
  s.iterations = ReadInt(j, "iterations");
  s.seed = ReadInt(j, "seed");
  const json& regimes = Key(j, "regimes");
  if (!regimes.is_array()) throw std::runtime_error("bound record: 'regimes' is not a list");
  for (const json& r : regimes) {
    const int v = r.is_number_integer() ? r.get<int>() : -1;
    if (v < 0 || v > static_cast<int>(ContactRegime::kFullLiftOff)) {
      throw std::runtime_error("bound record: unknown contact regime");
    }
    s.regimes.push_back(static_cast<ContactRegime>(v));
  }
  return s;
}

json LevelsRecord(const std::vector<LevelBound>& levels) {
  json a = json::array();
  for (const LevelBound& l : levels) {
    a.push_back({{"level", l.level},
                 {"parameters", l.parameters},
                 {"min", SolutionRecord(l.min)},
                 {"max", SolutionRecord(l.max)},
                 {"corners_solved", l.corners_solved},
                 {"corners_failed", l.corners_failed},
                 {"optimizer_runs", l.optimizer_runs},
                 {"samples_checked", l.samples_checked},
                 {"improved_by_samples", l.improved_by_samples},
                 {"raised_by_coarser", l.raised_by_coarser},
                 {"single_min", SolutionRecord(l.single_min)},
                 {"single_max", SolutionRecord(l.single_max)},
                 {"wall_s", Real(l.wall_s)},
                 {"refine_s", Real(l.refine_s)},
                 {"corners_s", Real(l.corners_s)}});
  }
  return a;
}

std::vector<LevelBound> LevelsFromRecord(const json& j) {
  std::vector<LevelBound> out;
  if (!j.contains("levels")) return out;  // a record of a one-level search
  const json& a = j.at("levels");
  if (!a.is_array()) throw std::runtime_error("bound record: 'levels' is not a list");
  for (const json& r : a) {
    LevelBound l;
    if (!Key(r, "level").is_string()) throw std::runtime_error("bound record: bad 'level'");
    l.level = r.at("level").get<std::string>();
    l.parameters = ReadInt(r, "parameters");
    l.min = SolutionFromRecord(Key(r, "min"));
    l.max = SolutionFromRecord(Key(r, "max"));
    l.corners_solved = ReadInt(r, "corners_solved");
    l.corners_failed = ReadInt(r, "corners_failed");
    l.optimizer_runs = ReadInt(r, "optimizer_runs");
    l.samples_checked = ReadInt(r, "samples_checked");
    l.improved_by_samples = ReadInt(r, "improved_by_samples");
    l.raised_by_coarser = ReadInt(r, "raised_by_coarser");
    l.single_min = SolutionFromRecord(Key(r, "single_min"));
    l.single_max = SolutionFromRecord(Key(r, "single_max"));
    l.wall_s = ReadReal(r, "wall_s");
    l.refine_s = ReadReal(r, "refine_s");
    l.corners_s = ReadReal(r, "corners_s");
    out.push_back(std::move(l));
  }
  return out;
}

json BoundsRecordOneLevel(const BoundsResult& b) {
  return {{"freq_hz", b.freq_hz},
          {"min", SolutionRecord(b.min)},
          {"max", SolutionRecord(b.max)},
          {"spread_min", Real(b.spread_min)},
          {"spread_max", Real(b.spread_max)},
          {"seeds_tried", b.seeds_tried},
          {"seed_counts",
           {{"base", b.seed_counts.base},
            {"group_patterns", b.seed_counts.group_patterns},
            {"random", b.seed_counts.random}}},
          {"seeds_converged", b.seeds_converged},
          {"start_failures", b.start_failures},
          {"min_failures", b.min_failures},
          {"max_failures", b.max_failures},
          {"optimizer_runs", b.optimizer_runs},
          {"runs_abandoned", b.runs_abandoned},
          {"samples_checked", b.samples_checked},
          {"samples_failed", b.samples_failed},
          {"improved_by_samples", b.improved_by_samples},
          {"search_harmonics", b.search_harmonics},
          {"refinement_fallbacks", b.refinement_fallbacks},
          {"harmonics", b.harmonics},
          {"wall_s", b.wall_s}};
}

}  // namespace

json BoundsRecord(const BoundsResult& b) {
  json j = BoundsRecordOneLevel(b);
  if (!b.levels.empty()) j["levels"] = LevelsRecord(b.levels);
  return j;
}

BoundsResult BoundsFromRecord(const json& j) {
  BoundsResult b;
  b.freq_hz = ReadReal(j, "freq_hz");
  if (!(b.freq_hz > 0.0)) throw std::runtime_error("bound record: 'freq_hz' must be positive");
  b.min = SolutionFromRecord(Key(j, "min"));
  b.max = SolutionFromRecord(Key(j, "max"));
  b.spread_min = ReadReal(j, "spread_min");
  b.spread_max = ReadReal(j, "spread_max");
  b.seeds_tried = ReadInt(j, "seeds_tried");
  const json& counts = Key(j, "seed_counts");
  b.seed_counts.base = ReadInt(counts, "base");
  b.seed_counts.group_patterns = ReadInt(counts, "group_patterns");
  b.seed_counts.random = ReadInt(counts, "random");
  b.seeds_converged = ReadInt(j, "seeds_converged");
  b.start_failures = ReadInt(j, "start_failures");
  b.min_failures = ReadInt(j, "min_failures");
  b.max_failures = ReadInt(j, "max_failures");
  b.optimizer_runs = ReadInt(j, "optimizer_runs");
  b.runs_abandoned = ReadInt(j, "runs_abandoned");
  b.samples_checked = ReadInt(j, "samples_checked");
  b.samples_failed = ReadInt(j, "samples_failed");
  b.improved_by_samples = ReadInt(j, "improved_by_samples");
  b.search_harmonics = ReadInt(j, "search_harmonics");
  b.refinement_fallbacks = ReadInt(j, "refinement_fallbacks");
  b.harmonics = ReadInt(j, "harmonics");
  b.wall_s = ReadReal(j, "wall_s");
  b.levels = LevelsFromRecord(j);
  return b;
}

json RobustnessRecord(const RobustnessPoint& p) {
  return {{"parameter", p.parameter},
          {"freq_hz", Real(p.freq_hz)},
          {"robustness", Real(p.robustness)},
          {"bound_solves", p.bound_solves},
          {"bounds", BoundsRecord(p.bounds)}};
}

RobustnessPoint RobustnessFromRecord(const json& j) {
  RobustnessPoint p;
  p.parameter = ReadReal(j, "parameter");
  p.freq_hz = ReadReal(j, "freq_hz");
  p.robustness = ReadReal(j, "robustness");
  p.bound_solves = ReadInt(j, "bound_solves");
  p.bounds = BoundsFromRecord(Key(j, "bounds"));
  return p;
}

}  // namespace fricrom::app
