// Internal to the `reduce` / `check-reduced` commands: JSON of the checks, the reduced model judged
// against the full one (eigenfrequency table, rigid-body modes and mass properties, static body
// load) and the reduced HDF5 file.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "fricrom/fe_model.h"
#include "fricrom/reduction.h"

namespace fricrom::app {

nlohmann::json ChecksJson(const CraigBamptonChecks& checks, double tolerance);
nlohmann::json MassJson(const MassProperties& p);
// Mean position of the nodes of `dofs` (those with coordinates in `model`).
Eigen::Vector3d Centroid(const FeModel& model, const std::vector<DofId>& dofs);

struct ReferenceInput {
  const FeModel* model = nullptr;  // node coordinates (rigid-body fields), may have none
  const FeMatrix* k = nullptr;
  const FeMatrix* m = nullptr;
  const BoundarySelection* boundary = nullptr;
  const ReducedModel* reduced = nullptr;
  const CraigBamptonSummary* summary = nullptr;
  double cutoff_hz = 0.0;  // 0: count mode
  int compare_modes = -1;  // < 0: the modes up to the cutoff / highest kept mode, <= 60
};

struct ReferenceReport {
  nlohmann::json table =
      nlohmann::json::array();            // mode, full_hz, reduced_hz, rel_error, rigid_body
  double max_err = 0.0;                   // NaN-propagating over the table
  double max_err_quarter = 0.0;           // over the modes with f <= f_top / 4
  nlohmann::json rigid = nullptr;         // free-body check, or why skipped
  nlohmann::json static_check = nullptr;  // static body load
  nlohmann::json timings = nlohmann::json::object();
  nlohmann::json shift = nullptr;  // shift of the full-model eigen solve
  // Eigenvalues of (K_r, M_r) that are infinite (massless boundary DOFs), dropped from the table.
  int reduced_infinite = 0;
  // Empty when the reference gives its evidence: full-model modes computed, every value finite,
  // each reduced eigenvalue >= the full one (Rayleigh-Ritz) to 1e-6. Otherwise why not.
  std::string failure;
};

// Compares the reduced model with the full one. The reduced matrices must be finite.
ReferenceReport CompareWithFullModel(const ReferenceInput& in,
                                     const std::function<void(const std::string&)>& progress);

struct ReducedFileInput {
  const FeModel* model = nullptr;
  const FeMatrix* mass = nullptr;  // full mass (unit acceleration loads when it has a DOF map)
  const BoundarySelection* boundary = nullptr;
  const ReducedModel* reduced = nullptr;
  const CraigBamptonSummary* summary = nullptr;
  std::string boundary_label;     // what selected the boundary (sets, ids or rows)
  std::vector<std::string> sets;  // node sets written under boundary/sets
  double cutoff_hz = 0.0;
  double modal_damping = -1.0;             // < 0: no damping matrix
  const nlohmann::json* report = nullptr;  // the command's JSON (checks, eigen_comparison)
};

// Writes the reduced model (schema fricrom-reduced-model-1) atomically to `path`.
void WriteReducedModel(const std::string& path, const ReducedFileInput& in);

}  // namespace fricrom::app
