// Case files (TOML): a lumped model of bodies, springs, wedge-damper contacts and loads, written
// entirely as data, with named parameters that any numeric value may use in an expression
// (e.g. theta = "theta_ref*(1-beta)"). Units: SI (m, kg, s, N, rad); frequencies in Hz.
// The schema is documented in docs/case-files.md.
#pragma once

#include <Eigen/Dense>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "fricrom/formulation.h"
#include "fricrom/model.h"

namespace fricrom {

// Bad input in a case file: names the file, the key (and line where known) and what was expected.
class CaseError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ParameterOverride {
  std::string name;
  double value = 0.0;
};
// Parses "name=value"; throws CaseError naming the text on bad syntax.
ParameterOverride ParseOverride(const std::string& text);

struct AnalysisSettings {
  int harmonics = 1;
  // Bounds: 0 searches at `harmonics`; 1 searches at H = 1 and refines the optima at
  // `harmonics` (BoundsOptions::search_harmonics).
  int search_harmonics = 0;
  int samples_per_period = 128;
  double freq_min_hz = 0.0;
  double freq_max_hz = 0.0;
  std::vector<double> alpha;                               // one per contact, default α
  BalanceKind balance = BalanceKind::kFull;                // full (lumped default) or condensed
  ReceptanceMethod receptance = ReceptanceMethod::kDense;  // linear part of the condensed balance
};

struct Case {
  std::string source;  // file path or a label
  std::string name;
  std::string description;
  std::map<std::string, double> parameters;  // after overrides
  Model model;
  AnalysisSettings analysis;
  std::vector<std::string> contact_names;
  // Interface (and tangential direction) of each solver α of an FE assembly, numbered from 0:
  // the groups of BoundsOptions::seed_groups. Empty for lumped cases.
  std::vector<int> alpha_interface;
  // Contact-state maps of FE assemblies: the placed position [m] of each contact's A-side node
  // (3 × contacts) and the index of its interface in interface_names. Empty for lumped cases and
  // for contacts given one by one.
  Eigen::Matrix3Xd contact_positions;
  std::vector<int> contact_interface;
  std::vector<std::string> interface_names;
  std::string resolved;  // the resolved case (parameters substituted) as TOML text
};

// Reads and builds a case. Unknown keys, missing keys, bad values and unknown override names
// throw CaseError.
Case LoadCase(const std::string& path, const std::vector<ParameterOverride>& overrides = {});
// Writes a lumped case as an FE assembly case (fricrom-assembly-1) in `directory`: the blades as
// one FE body with a node per blade, each damper a one-node FE body (Matrix Market K, M, C with a
// DOF map), the contacts as node pairs with their frames. Returns the case file's path. Throws
// CaseError when the model is not block-diagonal over those bodies.
std::string ExportAssembly(const Case& c, const std::string& directory);

Case ParseCase(const std::string& toml_text, const std::string& source_name,
               const std::vector<ParameterOverride>& overrides = {});

}  // namespace fricrom
