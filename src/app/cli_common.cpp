#include "app/cli_common.h"

#include <cmath>
#include <iostream>
#include <sstream>

#include "app/mpi_units.h"

namespace fricrom::app {

Case CaseArgs::Load(const std::vector<ParameterOverride>& extra) const {
  std::vector<ParameterOverride> overrides;
  for (const std::string& s : sets) overrides.push_back(ParseOverride(s));
  for (const ParameterOverride& o : extra) overrides.push_back(o);
  Case c = LoadCase(path, overrides);
  if (harmonics >= 0) c.analysis.harmonics = harmonics;
  if (samples >= 0) c.analysis.samples_per_period = samples;
  if (!balance.empty()) FromString(balance, &c.analysis.balance);           // checked by CLI11
  if (!receptance.empty()) FromString(receptance, &c.analysis.receptance);  // checked by CLI11
  HbmOptions ho{c.analysis.harmonics, c.analysis.samples_per_period, c.analysis.receptance};
  std::string error;
  if (!ho.IsValid(&error)) {
    throw CaseError(path + ": " + (harmonics >= 0 ? "--harmonics/--samples" : "analysis") + ": " +
                    error);
  }
  if (!LoadsRepresentable(c.model, ho.harmonics, &error)) {
    throw CaseError(path + ": loads: " + error +
                    (harmonics >= 0 ? " (--harmonics " : " (analysis.harmonics = ") +
                    std::to_string(ho.harmonics) + ")");
  }
  return c;
}

void CaseArgs::Register(CLI::App* cmd) {
  cmd->add_option("case", path, "Case file (TOML)")->required();
  cmd->add_option("--set", sets, "Override a case parameter, e.g. --set gamma=0.2 (repeatable)");
  cmd->add_option("--harmonics", harmonics, "Harmonics H (default: the case's)")
      ->check(CLI::Range(1, 200));
  cmd->add_option("--samples", samples, "AFT time samples per period (default: the case's)")
      ->check(CLI::Range(4, 1 << 20));
  cmd->add_option("--balance", balance,
                  "Harmonic balance: full (every DOF) or condensed (contact DOFs; default of FE "
                  "assemblies); default: the case's")
      ->check(CLI::IsMember({"full", "condensed"}));
  cmd->add_option("--receptance", receptance,
                  "Linear part of the condensed balance: dense (LU per frequency, exact) or modal "
                  "(one eigen-decomposition, fast; damping from diag(Phi^T C Phi)); default: the "
                  "case's")
      ->check(CLI::IsMember({"dense", "modal"}));
}

namespace {
CLI::Validator NumberAbove(double lower, bool inclusive, const std::string& what,
                           const std::string& name) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        double v = 0.0;
        size_t used = 0;
        try {
          v = std::stod(text, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        if (used == 0 || used != text.size() || !std::isfinite(v) ||
            !(inclusive ? v >= lower : v > lower)) {
          return "expected a finite number " + what + ", got '" + text + "'";
        }
        return "";
      },
      name);
}
}  // namespace

CLI::Validator Positive() { return NumberAbove(0.0, false, "> 0", "POSITIVE"); }
CLI::Validator NonNegative() { return NumberAbove(0.0, true, ">= 0", "NON-NEGATIVE"); }

CLI::Validator FractionBelowOne(bool zero_allowed) {
  const std::string range = zero_allowed ? "[0, 1)" : "(0, 1)";
  return CLI::Validator(
      [=](const std::string& v) {
        double r = 0.0;
        const bool number = CLI::detail::lexical_cast(v, r);
        return number && (zero_allowed ? r >= 0.0 : r > 0.0) && r < 1.0
                   ? std::string()
                   : "must be a number in " + range + ", got " + v;
      },
      "in " + range);
}

std::unique_ptr<HarmonicBalance> MakeCaseBalance(const Case& c) {
  return MakeBalance(
      c.model,
      HbmOptions{c.analysis.harmonics, c.analysis.samples_per_period, c.analysis.receptance},
      c.analysis.balance);
}

std::vector<double> ParseList(const std::string& text, const std::string& flag) {
  std::vector<double> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    try {
      size_t used = 0;
      const double v = std::stod(item, &used);
      while (used < item.size() && std::isspace(static_cast<unsigned char>(item[used]))) ++used;
      if (used != item.size() || !std::isfinite(v)) throw std::invalid_argument("");
      out.push_back(v);
    } catch (const std::exception&) {
      throw CLI::ValidationError(flag, "'" + item + "' is not a number (expected a comma list)");
    }
  }
  if (out.empty()) throw CLI::ValidationError(flag, "empty list");
  return out;
}

std::string Version() { return FRICROM_VERSION; }
std::string InstructionSet() { return FRICROM_INSTRUCTION_SET; }

void CommonAttributes(Hdf5Writer& h5, const Case& c, const std::string& command) {
  h5.Attribute("", "fricrom_version", Version());
  h5.Attribute("", "schema", "fricrom-results-1");
  h5.Attribute("", "units", "SI (m, N, s); frequencies in Hz");
  h5.Attribute("", "command", command);
  h5.Attribute("", "case_name", c.name);
  h5.Attribute("", "case_source", c.source);
  h5.Attribute("", "response_dof", c.model.dof_names[c.model.response_dof]);
  h5.String("case/resolved_toml", c.resolved);
}

std::vector<std::vector<int>> ContactsByDamper(const Model& model) {
  std::vector<std::vector<int>> groups;
  std::vector<std::vector<int>> keys;
  for (int i = 0; i < static_cast<int>(model.contacts.size()); ++i) {
    const std::vector<int>& key = model.contacts[i].dofs_a;
    size_t g = 0;
    while (g < keys.size() && keys[g] != key) ++g;
    if (g == keys.size()) {
      keys.push_back(key);
      groups.emplace_back();
    }
    groups[g].push_back(i);
  }
  return groups;
}

std::vector<bool> MixedConfiguration(const Model& model,
                                     const std::vector<ContactRegime>& regimes) {
  std::vector<bool> mixed;
  for (const std::vector<int>& group : ContactsByDamper(model)) {
    bool stick = false, slip = false;
    for (int c : group) {
      if (c >= static_cast<int>(regimes.size())) continue;
      stick |= regimes[c] == ContactRegime::kFullStick;
      slip |= regimes[c] == ContactRegime::kStickSlip || regimes[c] == ContactRegime::kFullSlip ||
              regimes[c] == ContactRegime::kStickSlipLiftOff;
    }
    mixed.push_back(stick && slip);
  }
  return mixed;
}

void WarnOutsideCaseRange(const Case& c, double freq_hz, const std::string& option) {
  const double lo = c.analysis.freq_min_hz, hi = c.analysis.freq_max_hz;
  if (freq_hz >= lo && freq_hz <= hi) return;
  if (MpiRank() != 0) return;
  std::cerr << "fricrom: warning: " << option << " " << freq_hz
            << " Hz lies outside the case's range [" << lo << ", " << hi << "] Hz\n";
}

std::vector<std::string> RegimeNames(const std::vector<ContactRegime>& regimes) {
  std::vector<std::string> out;
  for (ContactRegime r : regimes) out.push_back(ToString(r));
  return out;
}

std::vector<Eigen::VectorXd> ParseSeeds(const std::string& text, int num_contacts) {
  std::vector<Eigen::VectorXd> seeds;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ';')) {
    const std::vector<double> v = ParseList(item, "--seeds");
    if (static_cast<int>(v.size()) != num_contacts) {
      throw CLI::ValidationError("--seeds", "each seed needs " + std::to_string(num_contacts) +
                                                " values (one per contact), got '" + item + "'");
    }
    for (double a : v) {
      if (!(std::abs(a) <= 1.0))
        throw CLI::ValidationError("--seeds", "values must lie in [-1, 1]");
    }
    seeds.push_back(Eigen::Map<const Eigen::VectorXd>(v.data(), v.size()));
  }
  return seeds;
}

}  // namespace fricrom::app
