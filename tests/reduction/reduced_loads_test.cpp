// Body-acceleration loads on Craig-Bampton models (Tᵀ M g), against the full model: the free
// damper's reduced load does the full model's work m·a on a rigid translation; the clamped blade's
// static boundary deflection under an acceleration equals the full model's for any number of
// modes (K_r is block-diagonal and its boundary block is the Schur complement, so
// u_b = (K_bb - K_bi K_ii⁻¹ K_ib)⁻¹ (f_b + Ψᵀ f_i): static condensation, exact). The loads the
// contact preload comes from are therefore exact on the reduced model.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"  // GCC 12 false positive inside Eigen
#endif

#include "fricrom/reduced_loads.h"

#include <gtest/gtest.h>

#include <Eigen/SparseCholesky>
#include <string>
#include <vector>

#include "fricrom/fe_model.h"
#include "fricrom/reduction.h"
#include "test_models.h"

namespace fricrom {
namespace {

using testing::kMeshes;

struct Body {
  FeModel fe;
  const FeMatrix* k = nullptr;
  const FeMatrix* m = nullptr;
  BoundarySelection sel;
  Body(const std::string& deck, const std::vector<std::string>& sets) : fe(ReadFe(deck)) {
    k = fe.Find("STIFFNESS");
    m = fe.Find("MASS");
    sel = SelectBoundaryDofs(fe, *k, sets);
  }
  ReducedModel Reduce(int modes) const {
    CraigBamptonOptions opt;
    opt.num_modes = modes;
    CraigBamptonSummary s;
    ReducedModel r = ReduceCraigBampton(k->real, m->real, sel.indices, opt, &s);
    EXPECT_EQ(s.status, CraigBamptonStatus::kSuccess) << s.BriefReport();
    return r;
  }
};

TEST(ReducedLoads, FreeDamperAccelerationLoadDoesTheWorkOfItsMass) {
  const Body d(kMeshes + "damper/coarse/damper.inp", {"CONTACT_LEFT", "CONTACT_RIGHT"});
  const ReducedModel r = d.Reduce(6);
  const Eigen::MatrixXd loads = UnitAccelerationLoads(d.m->real, d.k->row_dofs, r);
  ASSERT_EQ(loads.rows(), r.stiffness.rows());
  const Eigen::Index nb = static_cast<Eigen::Index>(r.boundary_dofs.size());
  for (int k = 0; k < 3; ++k) {
    // Full model: gᵀ M g, the body's mass seen by a translation along k.
    Eigen::VectorXd g(d.m->rows);
    for (Eigen::Index i = 0; i < g.size(); ++i) g[i] = d.k->row_dofs[i].component == k + 1;
    const double mass_full = g.dot(d.m->real * g);
    EXPECT_NEAR(mass_full, 9.2865e-3, 1e-6);  // meshes/README.md
    // Reduced: the translation is [e_k on the boundary; 0] (constraint modes carry rigid motion).
    Eigen::VectorXd rk = Eigen::VectorXd::Zero(r.stiffness.rows());
    for (Eigen::Index b = 0; b < nb; ++b) rk[b] = d.sel.dofs[b].component == k + 1;
    EXPECT_NEAR(rk.dot(loads.col(k)), mass_full, 1e-12 * mass_full) << k;
    // and M_r rk, the free body's shortcut, is the same load.
    EXPECT_LT((r.mass * rk - loads.col(k)).norm(), 1e-10 * loads.col(k).norm()) << k;
  }
}

TEST(ReducedLoads, ClampedBladeStaticBoundaryDeflectionIsExact) {
  const Body b(kMeshes + "blade_sector/coarse/blade_sector.inp",
               {"CONTACT_LEFT", "CONTACT_RIGHT", "EXCITATION", "RESPONSE"});
  Eigen::VectorXd gz(b.m->rows);
  for (Eigen::Index i = 0; i < gz.size(); ++i) gz[i] = b.k->row_dofs[i].component == 3;
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> full(b.k->real);
  ASSERT_EQ(full.info(), Eigen::Success);
  const Eigen::VectorXd u_full = full.solve(b.m->real * gz);
  std::vector<double> errors;
  for (int modes : {2, 10, 40}) {
    const ReducedModel r = b.Reduce(modes);
    const Eigen::VectorXd load = UnitAccelerationLoads(b.m->real, b.k->row_dofs, r).col(2);
    // Also through ProjectLoad directly.
    EXPECT_LT((ProjectLoad(r, b.m->real * gz) - load).norm(), 1e-14 * load.norm());
    const Eigen::VectorXd u_red = r.stiffness.ldlt().solve(load);
    double num = 0, den = 0;
    for (size_t k = 0; k < r.boundary_dofs.size(); ++k) {
      num = std::max(num, std::abs(u_red[k] - u_full[r.boundary_dofs[k]]));
      den = std::max(den, std::abs(u_full[r.boundary_dofs[k]]));
    }
    errors.push_back(num / den);
  }
  for (double e : errors) EXPECT_LT(e, 1e-9);
  RecordProperty("max_rel_error_2_10_40_modes", std::to_string(errors[0]) + " " +
                                                    std::to_string(errors[1]) + " " +
                                                    std::to_string(errors[2]));
}

TEST(ReducedLoads, SizeMismatchIsAnError) {
  ReducedModel r;
  r.boundary_dofs = {0};
  r.interior_dofs = {1, 2};
  EXPECT_THROW(ProjectLoad(r, Eigen::VectorXd::Zero(2)), std::invalid_argument);
}

}  // namespace
}  // namespace fricrom
