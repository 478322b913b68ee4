#include "case_reader.h"

namespace fricrom::detail {

void ParseParameters(Reader& rd, const toml::table& root,
                     const std::vector<ParameterOverride>& overrides, Case* cs,
                     toml::table* resolved) {
  // Parameters: plain numbers, then CLI overrides (which must name an existing parameter).
  if (const toml::table* params = root["parameters"].as_table()) {
    for (const auto& [k, v] : *params) {
      const std::string key = "parameters." + std::string(k.str());
      if (!v.is_number()) rd.Fail(key, "parameters must be plain numbers", &v);
      cs->parameters[std::string(k.str())] = rd.Number(v, key);
    }
  } else if (root.get("parameters")) {
    rd.Fail("parameters", "expected a table", root.get("parameters"));
  }
  for (const ParameterOverride& o : overrides) {
    auto it = cs->parameters.find(o.name);
    if (it == cs->parameters.end()) {
      std::string names;
      for (const auto& [k, v] : cs->parameters) names += (names.empty() ? "" : ", ") + k;
      throw CaseError(rd.source() + ": --set " + o.name +
                      ": no such parameter (the case defines: " + names + ")");
    }
    it->second = o.value;
  }
  rd.SetParameters(&cs->parameters);
  if (resolved) {
    toml::table p;
    for (const auto& [k, v] : cs->parameters) p.insert(k, v);
    resolved->insert("parameters", std::move(p));
  }
}

void ParseAnalysis(const Reader& rd, const toml::table& root, const toml::array& loads,
                   size_t num_contacts, BalanceKind default_balance, AnalysisSettings* out,
                   toml::table* resolved) {
  const toml::node& an = rd.Require(root, "", "analysis");
  if (!an.is_table()) rd.Fail("analysis", "expected a table", &an);
  const toml::table& t = *an.as_table();
  const std::string w = "analysis";
  rd.CheckKeys(t, w,
               {"harmonics", "samples_per_period", "freq_min_hz", "freq_max_hz", "alpha", "balance",
                "receptance", "search_harmonics"});
  AnalysisSettings& a = *out;
  a.balance = default_balance;
  const double h = rd.Number(t, w, "harmonics");
  if (h < 1 || h != std::floor(h) || h > 200)
    rd.Fail(w + ".harmonics", "expected an integer in [1, 200]", t.get("harmonics"));
  a.harmonics = static_cast<int>(h);
  for (size_t i = 0; i < loads.size(); ++i) {  // a load H cannot represent is an error, not dropped
    const int lh = static_cast<int>(rd.Number(*loads[i].as_table(), "loads", "harmonic"));
    if (lh > a.harmonics) {
      rd.Fail("loads[" + std::to_string(i) + "].harmonic",
              "harmonic " + std::to_string(lh) + " exceeds analysis.harmonics = " +
                  std::to_string(a.harmonics) + " (raise harmonics or remove the load)",
              loads[i].as_table()->get("harmonic"));
    }
  }
  if (t.get("search_harmonics")) {
    const double sh = rd.Number(t, w, "search_harmonics");
    if (sh != 0 && sh != 1) {
      rd.Fail(w + ".search_harmonics",
              "expected 0 (the bounds' search at analysis.harmonics) or 1 (search at H = 1, "
              "optima refined at analysis.harmonics)",
              t.get("search_harmonics"));
    }
    a.search_harmonics = static_cast<int>(sh);
  }
  const double ns = rd.Number(t, w, "samples_per_period");
  if (ns != std::floor(ns) || ns <= 2 * h || ns < 4 || ns > 1 << 20) {
    rd.Fail(w + ".samples_per_period", "expected an integer >= 4 and > 2*harmonics",
            t.get("samples_per_period"));
  }
  a.samples_per_period = static_cast<int>(ns);
  a.freq_min_hz = rd.Positive(t, w, "freq_min_hz");
  a.freq_max_hz = rd.Positive(t, w, "freq_max_hz");
  if (!(a.freq_max_hz > a.freq_min_hz))
    rd.Fail(w + ".freq_max_hz", "must exceed freq_min_hz", t.get("freq_max_hz"));
  if (t.get("alpha")) {
    const toml::array& al = rd.Array(t, w, "alpha");
    for (size_t i = 0; i < al.size(); ++i) {
      const double v = rd.Number(al[i], w + ".alpha[" + std::to_string(i) + "]");
      if (!(std::abs(v) <= 1.0))
        rd.Fail(w + ".alpha[" + std::to_string(i) + "]", "expected a value in [-1, 1]", &al[i]);
      a.alpha.push_back(v);
    }
    if (a.alpha.size() != num_contacts) {
      rd.Fail(w + ".alpha", "expected one value per contact (" + std::to_string(num_contacts) + ")",
              t.get("alpha"));
    }
  } else {
    a.alpha.assign(num_contacts, 0.0);
  }
  if (t.get("balance")) {
    const std::string b = rd.String(t, w, "balance");
    if (!FromString(b, &a.balance))
      rd.Fail(w + ".balance", "expected \"full\" or \"condensed\", got '" + b + "'",
              t.get("balance"));
  }
  if (t.get("receptance")) {
    const std::string r = rd.String(t, w, "receptance");
    if (!FromString(r, &a.receptance))
      rd.Fail(w + ".receptance", "expected \"dense\" or \"modal\", got '" + r + "'",
              t.get("receptance"));
  }
  toml::array ra;
  for (double v : a.alpha) ra.push_back(v);
  if (resolved)
    resolved->insert("analysis", toml::table{{"harmonics", a.harmonics},
                                             {"samples_per_period", a.samples_per_period},
                                             {"freq_min_hz", a.freq_min_hz},
                                             {"freq_max_hz", a.freq_max_hz},
                                             {"alpha", std::move(ra)},
                                             {"balance", ToString(a.balance)},
                                             {"receptance", ToString(a.receptance)},
                                             {"search_harmonics", a.search_harmonics}});
}

void FinishCase(const toml::table& resolved, Case* cs) {
  try {
    cs->model.Validate();
  } catch (const std::invalid_argument& e) {
    throw CaseError(cs->source + ": inconsistent model: " + e.what());
  }
  std::ostringstream out;
  out << resolved;
  cs->resolved = out.str();
}

}  // namespace fricrom::detail
