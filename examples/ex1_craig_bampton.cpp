// Example 1: Craig-Bampton reduction of a blade sector onto its contact nodes.
//
//   build/examples/ex1_craig_bampton [meshes/blade_sector/coarse/blade_sector.inp] [cutoff_hz]
//
// The steps a user of the library goes through, in order: read the FE model exported by
// CalculiX, choose the boundary from its node sets, reduce, and judge the reduced model against
// the full one. Also run by ctest (Examples.CraigBampton): exit status 0 only if every check
// below holds. Units SI.
#include <cmath>
#include <cstdio>
#include <exception>
#include <numbers>
#include <string>
#include <vector>

#include "fricrom/fe_model.h"
#include "fricrom/reduction.h"

int main(int argc, char** argv) {
  const std::string deck = argc > 1 ? argv[1] : "meshes/blade_sector/coarse/blade_sector.inp";
  const double cutoff_hz = argc > 2 ? std::stod(argv[2]) : 50e3;
  try {
    // 1. Read the model: job.inp (nodes, node sets) with job.sti / job.mas / job.dof beside it.
    const fricrom::FeModel model = fricrom::ReadFe(deck);
    const fricrom::FeMatrix* k = model.Find("STIFFNESS");
    const fricrom::FeMatrix* m = model.Find("MASS");
    if (!k || !m) {
      std::fprintf(stderr, "%s: no STIFFNESS/MASS matrices\n", deck.c_str());
      return 2;
    }
    std::printf("1. %s: %lld DOFs, %zu nodes, %zu node sets\n", deck.c_str(),
                static_cast<long long>(k->rows), model.nodes.size(), model.node_sets.size());

    // 2. Boundary: the nodes where friction contacts and loads will act stay physical.
    const fricrom::BoundarySelection boundary = fricrom::SelectBoundaryDofs(
        model, *k, {"CONTACT_LEFT", "CONTACT_RIGHT", "EXCITATION", "RESPONSE"});
    std::printf("2. boundary: %zu DOFs on %zu nodes\n", boundary.indices.size(),
                boundary.nodes.size());

    // 3. Reduce: every fixed-interface mode up to the cutoff (no more than the range needs).
    fricrom::CraigBamptonOptions options;
    options.cutoff_hz = cutoff_hz;
    std::string why;
    if (!options.IsValid(&why)) {
      std::fprintf(stderr, "options: %s\n", why.c_str());
      return 2;
    }
    fricrom::CraigBamptonSummary summary;
    const fricrom::ReducedModel reduced =
        fricrom::ReduceCraigBampton(k->real, m->real, boundary.indices, options, &summary);
    std::printf("3. %s\n", summary.BriefReport().c_str());
    if (!summary.IsSolutionUsable()) return 1;

    // 4. Judge it: the full model's lowest modes (ARPACK on the full matrices) against the
    //    reduced model's. Rayleigh-Ritz: the reduced frequencies are upper bounds.
    fricrom::ModalSolveOptions reference;
    reference.num_modes = 6;
    const fricrom::ModalSolveResult full = fricrom::SolveLowestModes(k->real, m->real, reference);
    if (full.status != fricrom::ModalSolveStatus::kSuccess) {
      std::fprintf(stderr, "full model: %s\n", full.message.c_str());
      return 1;
    }
    const Eigen::VectorXd lambda = fricrom::ReducedEigenvalues(reduced.stiffness, reduced.mass);
    bool ok = true;
    std::printf("4. mode   full [Hz]   reduced [Hz]   rel. error\n");
    for (int j = 0; j < full.frequencies_hz.size(); ++j) {
      const double f_full = full.frequencies_hz(j);
      const double f_red = std::sqrt(lambda(j)) / (2 * std::numbers::pi);
      const double e = (f_red - f_full) / f_full;
      std::printf("   %4d %11.3f %14.3f %12.2e\n", j + 1, f_full, f_red, e);
      ok = ok && e > -1e-9 && (f_full > cutoff_hz / 40 || e < 1e-6);
    }

    // 5. The static response at the contact nodes to an interior load is exact (constraint
    //    modes); the interior recovered from the reduced coordinates converges with the modes.
    const fricrom::StaticCheckResult st = fricrom::CompareStaticBodyLoad(
        k->real, m->real, k->row_dofs, reduced, Eigen::Vector3d(0, 0, -9.81));
    std::printf("5. body load: boundary error %.1e, interior error %.1e\n", st.rel_error,
                st.interior_rel_error);
    ok = ok && st.solved && st.rel_error < 1e-9 && summary.checks.Max() < 1e-10;
    std::printf("%s\n", ok ? "all checks passed" : "CHECK FAILED");
    return ok ? 0 : 1;
  } catch (const std::exception& e) {  // bad file, unknown node set, ...
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
}
