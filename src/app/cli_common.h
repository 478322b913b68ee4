// Pieces shared by the CLI commands: case arguments, list parsing, result-file attributes.
#pragma once

#include <CLI/CLI.hpp>
#include <Eigen/Dense>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "fricrom/balance.h"
#include "fricrom/case_file.h"
#include "fricrom/contact_law.h"
#include "fricrom/hbm_system.h"
#include "io/hdf5_file.h"

namespace fricrom::app {

// A run that cannot produce its result because a solve did not converge (exit status 1, not the
// bad-input status 2).
class NotConverged : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct CaseArgs {
  std::string path;
  std::vector<std::string> sets;
  int harmonics = -1;
  int samples = -1;
  std::string balance;     // "" = the case's
  std::string receptance;  // "" = the case's

  // Loads the case with the overrides; extra overrides (e.g. a swept parameter) come last.
  Case Load(const std::vector<ParameterOverride>& extra = {}) const;
  void Register(CLI::App* cmd);
};

// "> 0 and finite" / ">= 0 and finite", with a short message (CLI11's own prints DBL_MAX in full).
CLI::Validator Positive();
CLI::Validator NonNegative();
// A fraction in [0, 1) (zero_allowed) or (0, 1): "must be a number in [0, 1), got ...".
CLI::Validator FractionBelowOne(bool zero_allowed);

// The harmonic-balance problem of a loaded case (full or condensed, analysis.balance).
std::unique_ptr<HarmonicBalance> MakeCaseBalance(const Case& c);

std::vector<double> ParseList(const std::string& text, const std::string& flag);
// --seeds "a,b,c,d;e,f,g,h": semicolon-separated α vectors of num_contacts values in [-1, 1].
std::vector<Eigen::VectorXd> ParseSeeds(const std::string& text, int num_contacts);
std::string Version();
// The instruction set the build targets ("x86-64-v3" or "portable", cmake/FricromCpuTarget.cmake):
// results of the two differ at round-off, so manifests and --version name it.
std::string InstructionSet();
void CommonAttributes(Hdf5Writer& h5, const Case& c, const std::string& command);

// Contacts grouped by the body on their A side (the damper): indices into model.contacts.
std::vector<std::vector<int>> ContactsByDamper(const Model& model);
// A damper is in the paper's "mixed configuration" when one of its contacts sticks over the whole
// period and another slips during it.
std::vector<bool> MixedConfiguration(const Model& model, const std::vector<ContactRegime>& regimes);
std::vector<std::string> RegimeNames(const std::vector<ContactRegime>& regimes);
// A warning on stderr (rank 0) where a frequency given on the command line lies outside the
// case's [freq_min_hz, freq_max_hz]: allowed, but usually a unit or typing slip.
void WarnOutsideCaseRange(const Case& c, double freq_hz, const std::string& option);

}  // namespace fricrom::app
