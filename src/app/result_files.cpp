#include "app/result_files.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <tuple>
#include <utility>

#include "app/cli_common.h"
#include "fricrom/blas_core.h"
#include "fricrom/linear.h"
#include "fricrom/units.h"
#include "io/atomic_file.h"
#include "io/content_hash.h"
#include "io/hdf5_file.h"

namespace fricrom::app {

using json = nlohmann::json;

json NumberOrNull(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }
std::vector<double> ToStd(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }
std::string Status(const BoundSolution& s) { return ToString(s.status); }

static void WriteHistories(Hdf5Writer& h5, const std::string& group, const HarmonicBalance& system,
                           const BoundSolution& s, double freq_hz) {
  if (!s.IsUsable()) return;
  const auto hist = system.ContactHistories(s.x, RadPerS(freq_hz), s.alpha);
  const int nc = static_cast<int>(hist.size());
  const int n = static_cast<int>(hist[0].time_s.size());
  Eigen::MatrixXd t(nc, n), nn(nc, n), st(nc, n);
  std::vector<std::string> regimes;
  for (int c = 0; c < nc; ++c) {
    t.row(c) = hist[c].tangential.transpose();
    nn.row(c) = hist[c].normal.transpose();
    for (int k = 0; k < n; ++k) st(c, k) = static_cast<double>(hist[c].states[k]);
    regimes.push_back(ToString(hist[c].regime));
  }
  h5.Vector(group + "/time_s", hist[0].time_s);
  h5.Matrix(group + "/tangential_N", t);
  h5.Matrix(group + "/normal_N", nn);
  h5.Matrix(group + "/states", st);
  h5.Strings(group + "/regimes", regimes);
  h5.Vector(group + "/alpha", s.alpha);
  h5.Attribute(group, "freq_hz", freq_hz);
  h5.Attribute(group, "amplitude_m", s.amplitude);
  h5.Attribute(group, "states_legend", "0 stick, 1 positive slip, 2 negative slip, 3 lift-off");
}

json BoundsJson(const Model& model, const BoundsResult& b) {
  json j;
  j["freq_hz"] = b.freq_hz;
  j["point_wall_s"] = b.wall_s;
  j["contact_pairs"] = model.num_contact_pairs();
  j["alpha_count"] = b.min.alpha.size() > 0 ? b.min.alpha.size() : model.num_alpha();
  j["y_min"] = NumberOrNull(b.min.amplitude);
  j["y_max"] = NumberOrNull(b.max.amplitude);
  // the maximum response has the minimum loss factor
  j["eta_min"] = NumberOrNull(b.max.loss_factor);
  j["eta_max"] = NumberOrNull(b.min.loss_factor);
  j["alpha_at_min"] = ToStd(b.min.alpha);
  j["alpha_at_max"] = ToStd(b.max.alpha);
  j["states_at_min"] = RegimeNames(b.min.regimes);
  j["states_at_max"] = RegimeNames(b.max.regimes);
  j["mixed_configuration_at_min"] = MixedConfiguration(model, b.min.regimes);
  j["mixed_configuration_at_max"] = MixedConfiguration(model, b.max.regimes);
  j["R"] = NumberOrNull(b.robustness());
  j["status"] = b.IsUsable() ? "converged" : "min: " + Status(b.min) + ", max: " + Status(b.max);
  j["status_min"] = Status(b.min);
  j["status_max"] = Status(b.max);
  // false: the bound is a feasible point beyond every stationary point its runs reached.
  j["stationary_min"] = b.min.IsUsable() ? json(b.min.stationary) : json(nullptr);
  j["stationary_max"] = b.max.IsUsable() ? json(b.max.stationary) : json(nullptr);
  // Hill stability of each bound's solution (null where not computed; the note says why).
  for (const auto& [key, s] :
       {std::pair{"stability_min", &b.min}, std::pair{"stability_max", &b.max}}) {
    j[key] = {{"stable", s->stability.computed ? json(s->stability.stable) : json(nullptr)},
              {"max_floquet_real_per_s", NumberOrNull(s->stability.max_floquet_real)},
              {"note", s->stability.note}};
  }
  // The bounds over stable solutions (bounds --stable-only; null where not computed or where no
  // candidate is stable).
  if (b.stable.candidates > 0) {
    const StableBounds& st = b.stable;
    for (const auto& [key, s, exact] : {std::tuple{"stable_min", &st.min, st.exact_min},
                                        std::tuple{"stable_max", &st.max, st.exact_max}}) {
      j[key] = std::isfinite(s->amplitude)
                   ? json{{"amplitude_m", s->amplitude},
                          {"exact", exact},
                          {"max_floquet_real_per_s", NumberOrNull(s->stability.max_floquet_real)},
                          {"alpha", ToStd(s->alpha)}}
                   : json(nullptr);
    }
    j["R_stable"] = NumberOrNull(st.robustness());
    j["stable_candidates"] = {{"judged", st.candidates},
                              {"stable", st.stable},
                              {"approximate", st.approximate},
                              {"failed", st.failed},
                              {"beyond_bounds", st.beyond_bounds}};
  }
  j["spread_min"] = b.spread_min;
  j["spread_max"] = b.spread_max;
  j["seeds_tried"] = b.seeds_tried;
  j["seeds_converged"] = b.seeds_converged;
  j["optimizer_runs"] = b.optimizer_runs;
  j["runs_abandoned"] = b.runs_abandoned;
  j["seeds"] = {{"tried", b.seeds_tried},
                {"base", b.seed_counts.base},
                {"interface_patterns", b.seed_counts.group_patterns},
                {"random", b.seed_counts.random}};
  j["samples_checked"] = b.samples_checked;
  j["samples_failed"] = b.samples_failed;
  j["improved_by_samples"] = b.improved_by_samples;
  j["search_harmonics"] = b.search_harmonics;
  j["refinement_fallbacks"] = b.refinement_fallbacks;
  // The α levels of the search, coarsest first: each level's bounds [m] contain the coarser
  // levels'; the finest is the point's own (after a curve's neighbour pass).
  json levels = json::array();
  for (size_t l = 0; l < b.levels.size(); ++l) {
    const LevelBound& lv = b.levels[l];
    const bool own = l + 1 == b.levels.size();
    const BoundSolution& lo = own ? b.min : lv.min;
    const BoundSolution& hi = own ? b.max : lv.max;
    const double r = lo.IsUsable() && hi.IsUsable() && hi.amplitude > 0.0
                         ? lo.amplitude / hi.amplitude
                         : std::numeric_limits<double>::quiet_NaN();
    levels.push_back({{"level", lv.level},
                      {"parameters", lv.parameters},
                      {"y_min", NumberOrNull(lo.amplitude)},
                      {"y_max", NumberOrNull(hi.amplitude)},
                      {"R", NumberOrNull(r)},
                      {"alpha_at_min", own ? json(nullptr) : json(ToStd(lv.min.alpha))},
                      {"alpha_at_max", own ? json(nullptr) : json(ToStd(lv.max.alpha))},
                      {"corners_solved", lv.corners_solved},
                      {"corners_failed", lv.corners_failed},
                      {"optimizer_runs", lv.optimizer_runs},
                      {"samples_checked", lv.samples_checked},
                      {"raised_by_coarser", lv.raised_by_coarser},
                      {"wall_s", NumberOrNull(lv.wall_s)},
                      {"refine_s", NumberOrNull(lv.refine_s)},
                      {"corners_s", NumberOrNull(lv.corners_s)}});
  }
  j["levels"] = levels;
  return j;
}

bool HasContactMap(const Case& c) {
  return !c.interface_names.empty() &&
         c.contact_positions.cols() == static_cast<Eigen::Index>(c.model.contacts.size()) &&
         c.contact_interface.size() == c.model.contacts.size();
}

namespace {

// Hill stability of each bound and, with bounds --stable-only, the bounds over stable
// candidates (NaN where not computed or none stable) with their largest Floquet exponents.
void WriteStableBounds(Hdf5Writer& h5, const BoundCurve& curve) {
  std::vector<double> hmin, hmax, smin, smax, fmin, fmax;
  bool any = false;
  for (const BoundsResult& b : curve.points) {
    hmin.push_back(b.min.stability.max_floquet_real);
    hmax.push_back(b.max.stability.max_floquet_real);
    const bool on = b.stable.candidates > 0;
    any = any || on;
    smin.push_back(on ? b.stable.min.amplitude : NAN);
    smax.push_back(on ? b.stable.max.amplitude : NAN);
    fmin.push_back(on ? b.stable.min.stability.max_floquet_real : NAN);
    fmax.push_back(on ? b.stable.max.stability.max_floquet_real : NAN);
  }
  h5.Vector("bounds/max_floquet_real_min_per_s", hmin);
  h5.Vector("bounds/max_floquet_real_max_per_s", hmax);
  if (!any) return;
  h5.Vector("bounds/stable_y_min_m", smin);
  h5.Vector("bounds/stable_y_max_m", smax);
  h5.Vector("bounds/stable_max_floquet_real_min_per_s", fmin);
  h5.Vector("bounds/stable_max_floquet_real_max_per_s", fmax);
}

}  // namespace

void WriteBoundCurveFiles(const Case& c, const HarmonicBalance& system, const BoundCurve& curve,
                          const ResultFiles& files) {
  const BoundsResult& at = curve.points[curve.HasPeak() ? curve.peak : 0];
  {
    Hdf5Writer h5(files.hdf5);
    CommonAttributes(h5, c, "bounds");
    const int nc = system.num_alpha();
    std::vector<double> f, ymin, ymax, emin, emax, rr, wall;
    std::vector<std::string> smin, smax, rmin, rmax;
    Eigen::MatrixXd amin(curve.points.size(), nc), amax(curve.points.size(), nc);
    for (size_t i = 0; i < curve.points.size(); ++i) {
      const BoundsResult& b = curve.points[i];
      f.push_back(b.freq_hz);
      ymin.push_back(b.min.amplitude);
      ymax.push_back(b.max.amplitude);
      emin.push_back(b.max.loss_factor);
      emax.push_back(b.min.loss_factor);
      rr.push_back(b.robustness());
      wall.push_back(b.wall_s);
      smin.push_back(Status(b.min));
      smax.push_back(Status(b.max));
      amin.row(i).setConstant(NAN);
      amax.row(i).setConstant(NAN);
      if (b.min.alpha.size() == nc) amin.row(i) = b.min.alpha.transpose();
      if (b.max.alpha.size() == nc) amax.row(i) = b.max.alpha.transpose();
      for (int k = 0; k < nc; ++k) {
        rmin.push_back(k < static_cast<int>(b.min.regimes.size()) ? ToString(b.min.regimes[k])
                                                                  : "unknown");
        rmax.push_back(k < static_cast<int>(b.max.regimes.size()) ? ToString(b.max.regimes[k])
                                                                  : "unknown");
      }
    }
    h5.Vector("bounds/freq_hz", f);
    h5.Vector("bounds/y_min_m", ymin);
    h5.Vector("bounds/y_max_m", ymax);
    h5.Vector("bounds/eta_min", emin);
    h5.Vector("bounds/eta_max", emax);
    h5.Vector("bounds/robustness", rr);
    h5.Vector("bounds/wall_s", wall);  // per frequency: where a curve spends its time
    h5.Strings("bounds/status_min", smin);
    h5.Strings("bounds/status_max", smax);
    h5.Matrix("bounds/alpha_at_min", amin);
    h5.Matrix("bounds/alpha_at_max", amax);
    h5.Strings("bounds/regimes_min", rmin);
    h5.Strings("bounds/regimes_max", rmax);
    WriteStableBounds(h5, curve);
    h5.Attribute("bounds", "peak_freq_hz",
                 curve.HasPeak() ? curve.points[curve.peak].freq_hz : NAN);
    h5.Attribute("bounds", "robustness_at_peak",
                 curve.HasPeak() ? curve.points[curve.peak].robustness() : NAN);
    h5.Attribute("bounds", "wall_s", curve.wall_s);
    // The linear references span the curve (bounds --range), or the case's range for one point.
    double lo = c.analysis.freq_min_hz, hi = c.analysis.freq_max_hz;
    if (curve.points.size() > 1) {
      lo = hi = curve.points.front().freq_hz;
      for (const BoundsResult& b : curve.points) {
        lo = std::min(lo, b.freq_hz);
        hi = std::max(hi, b.freq_hz);
      }
    }
    std::vector<double> lf;
    for (int i = 0; i < 400; ++i) lf.push_back(lo + (hi - lo) * i / 399.0);
    h5.Vector("linear/freq_hz", lf);
    h5.Vector("linear/free_amplitude_m",
              LinearResponseAmplitude(c.model, LinearSystemKind::kFree, lf, c.analysis.receptance));
    h5.Vector("linear/stick_amplitude_m", LinearResponseAmplitude(c.model, LinearSystemKind::kStick,
                                                                  lf, c.analysis.receptance));
    h5.Strings("histories/contacts", c.contact_names);
    std::vector<double> mu;
    for (const Contact& ct : c.model.contacts) mu.push_back(ct.mu);
    h5.Vector("histories/mu", mu);
    WriteHistories(h5, "histories/min", system, at.min, at.freq_hz);
    WriteHistories(h5, "histories/max", system, at.max, at.freq_hz);
    if (HasContactMap(c)) {
      h5.Matrix("contact_map/position_m", c.contact_positions.transpose());
      h5.Vector("contact_map/interface",
                std::vector<double>(c.contact_interface.begin(), c.contact_interface.end()));
      h5.Strings("contact_map/interface_names", c.interface_names);
    }
    h5.Commit();
  }
  {
    std::ostringstream csv;
    csv << "# fricrom " << Version() << " bounds of " << c.name << "; units: Hz, m\n";
    csv << "freq_hz,y_min_m,y_max_m,eta_min,eta_max,R,status_min,status_max\n"
        << std::setprecision(12);
    for (const BoundsResult& b : curve.points) {
      csv << b.freq_hz << "," << b.min.amplitude << "," << b.max.amplitude << ","
          << b.max.loss_factor << "," << b.min.loss_factor << "," << b.robustness() << ","
          << Status(b.min) << "," << Status(b.max) << "\n";
    }
    WriteTextAtomically(files.csv, csv.str());
  }
}

nlohmann::json SweepRowJson(const Model& model, const RobustnessPoint& p) {
  return {{"R", NumberOrNull(p.robustness)},
          {"y_min", NumberOrNull(p.bounds.min.amplitude)},
          {"y_max", NumberOrNull(p.bounds.max.amplitude)},
          {"eta_min", NumberOrNull(p.bounds.max.loss_factor)},
          {"eta_max", NumberOrNull(p.bounds.min.loss_factor)},
          {"freq_hz", NumberOrNull(p.freq_hz)},
          {"status", p.bounds.IsUsable() ? "converged" : "failed"},
          {"states_min", RegimeNames(p.bounds.min.regimes)},
          {"states_max", RegimeNames(p.bounds.max.regimes)},
          {"mixed_min", MixedConfiguration(model, p.bounds.min.regimes)},
          {"mixed_max", MixedConfiguration(model, p.bounds.max.regimes)},
          {"bound_solves", p.bound_solves}};
}

void AppendSweepRow(const nlohmann::json& row, SweepColumns* s) {
  auto num = [&](const char* key) {
    const nlohmann::json& v = row.at(key);
    return v.is_null() ? std::numeric_limits<double>::quiet_NaN() : v.get<double>();
  };
  s->r.push_back(num("R"));
  s->ymin.push_back(num("y_min"));
  s->ymax.push_back(num("y_max"));
  s->emin.push_back(num("eta_min"));
  s->emax.push_back(num("eta_max"));
  s->fr.push_back(num("freq_hz"));
  s->st.push_back(row.at("status").get<std::string>());
  s->states_min.push_back(row.at("states_min"));
  s->states_max.push_back(row.at("states_max"));
  s->mixed_min.push_back(row.at("mixed_min"));
  s->mixed_max.push_back(row.at("mixed_max"));
  s->bound_solves += row.at("bound_solves").get<int>();
}

SweepColumns MakeSweepColumns(const Model& model, const std::vector<RobustnessPoint>& pts) {
  SweepColumns s;
  for (const RobustnessPoint& p : pts) AppendSweepRow(SweepRowJson(model, p), &s);
  return s;
}

void WriteSweepFiles(const Case& c0, const std::string& param, const std::vector<double>& values,
                     const SweepColumns& cols, double reference_freq_hz, double wall_s, int solves,
                     const ResultFiles& files) {
  {
    Hdf5Writer h5(files.hdf5);
    CommonAttributes(h5, c0, "sweep");
    h5.Vector("sweep/values", values);
    h5.Vector("sweep/robustness", cols.r);
    h5.Vector("sweep/y_min_m", cols.ymin);
    h5.Vector("sweep/y_max_m", cols.ymax);
    h5.Vector("sweep/eta_min", cols.emin);
    h5.Vector("sweep/eta_max", cols.emax);
    h5.Vector("sweep/freq_hz", cols.fr);
    h5.Strings("sweep/status", cols.st);
    h5.Attribute("sweep", "param", param);
    h5.Attribute("sweep", "reference_freq_hz", reference_freq_hz);
    h5.Attribute("sweep", "wall_s", wall_s);
    h5.Attribute("sweep", "inner_solves", static_cast<double>(solves));
    h5.Commit();
  }
  {
    std::ostringstream csv;
    csv << "# fricrom " << Version() << " sweep of " << param << " on " << c0.name
        << "; units: -, Hz, m\n";
    csv << param << ",R,freq_hz,y_min_m,y_max_m,eta_min,eta_max,status\n" << std::setprecision(12);
    for (size_t i = 0; i < cols.r.size(); ++i) {
      csv << values[i] << "," << cols.r[i] << "," << cols.fr[i] << "," << cols.ymin[i] << ","
          << cols.ymax[i] << "," << cols.emin[i] << "," << cols.emax[i] << "," << cols.st[i]
          << "\n";
    }
    WriteTextAtomically(files.csv, csv.str());
  }
}

void WriteManifest(const std::filesystem::path& dir, const std::string& name,
                   const std::vector<std::filesystem::path>& files) {
  nlohmann::json list = nlohmann::json::array();
  for (const std::filesystem::path& f : files) {
    Hasher h;
    HashFile(f.string(), &h);
    list.push_back({{"file", f.filename().string()},
                    {"bytes", std::filesystem::file_size(f)},
                    {"content", h.Hex()}});
  }
  const nlohmann::json m = {
      {"manifest", "fricrom-manifest-1"},
      {"command", name},
      {"fricrom", Version()},
      {"build", {{"instruction_set", InstructionSet()}, {"blas", BlasCoreReport()}}},
      {"files", list}};
  WriteTextAtomically(dir / (name + ".manifest.json"), m.dump(1) + "\n");
}

}  // namespace fricrom::app
