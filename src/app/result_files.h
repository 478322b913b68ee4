// One writer per result file type of the design commands (bound curves, sweeps): HDF5 and CSV
// files with the case's attributes, and the JSON of a bound computation. Units: SI (m, Hz, N).
#pragma once

#include <Eigen/Dense>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "fricrom/bounds.h"
#include "fricrom/case_file.h"
#include "fricrom/design.h"
#include "fricrom/harmonic_balance.h"

namespace fricrom::app {

// A finite number, or null: failed values are never numbers in the JSON.
nlohmann::json NumberOrNull(double v);
std::vector<double> ToStd(const Eigen::VectorXd& v);
std::string Status(const BoundSolution& s);

// The JSON of one bound computation (the keys of `fricrom bounds --json`).
nlohmann::json BoundsJson(const Model& model, const BoundsResult& b);

struct ResultFiles {
  std::filesystem::path hdf5, csv;
};

// The case places its contacts on interface faces (FE assemblies): a contact-state map can be
// drawn.
bool HasContactMap(const Case& c);

// bounds.h5 (curve, linear references, contact histories and contact-state map data at the
// peak) and bounds.csv.
void WriteBoundCurveFiles(const Case& c, const HarmonicBalance& system, const BoundCurve& curve,
                          const ResultFiles& files);

// The columns of a robustness sweep, per value.
struct SweepColumns {
  std::vector<double> r, ymin, ymax, emin, emax, fr;
  std::vector<std::string> st;
  nlohmann::json states_min = nlohmann::json::array(), states_max = nlohmann::json::array(),
                 mixed_min = nlohmann::json::array(), mixed_max = nlohmann::json::array();
  int bound_solves = 0;
};
SweepColumns MakeSweepColumns(const Model& model, const std::vector<RobustnessPoint>& pts);
// One value's columns as JSON (NaN as null): the unit result a sweep journal records, read back
// by AppendSweepRow (null as NaN) so a resumed sweep writes the same files.
nlohmann::json SweepRowJson(const Model& model, const RobustnessPoint& p);
void AppendSweepRow(const nlohmann::json& row, SweepColumns* cols);
// sweep.h5 and sweep.csv; reference_freq_hz NaN when the peak was tracked.
void WriteSweepFiles(const Case& c0, const std::string& param, const std::vector<double>& values,
                     const SweepColumns& cols, double reference_freq_hz, double wall_s, int solves,
                     const ResultFiles& files);

// The set of files one run wrote: dir/<name>.manifest.json (written last, atomically) lists each
// file with its size and content hash, so a reader can tell a complete set from a mix of two runs
// (each file is replaced atomically, but not all of them at once).
void WriteManifest(const std::filesystem::path& dir, const std::string& name,
                   const std::vector<std::filesystem::path>& files);

}  // namespace fricrom::app
