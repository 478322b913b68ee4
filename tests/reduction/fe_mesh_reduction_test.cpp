// Craig-Bampton on the committed CalculiX meshes (meshes/, made with gmsh + ccx):
//  * blade sector clamped at the root, boundary = contact faces + excitation + response nodes:
//    reduced eigenfrequencies against the full model's (ARPACK on the full matrices);
//  * free-free wedge damper, boundary = its two contact faces: six rigid-body modes, and mass,
//    centre of mass and inertia against the closed form of the extruded hexagonal section.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"  // GCC 12 false positive inside Eigen
#endif

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "fricrom/fe_model.h"
#include "fricrom/reduction.h"
#include "fricrom/units.h"
#include "test_models.h"

namespace fricrom {
namespace {

using testing::kMeshes;
const std::vector<std::string> kBladeSets = {"CONTACT_LEFT", "CONTACT_RIGHT", "EXCITATION",
                                             "RESPONSE"};

struct Model {
  FeModel fe;
  const FeMatrix* k = nullptr;
  const FeMatrix* m = nullptr;
  explicit Model(const std::string& deck) : fe(ReadFe(deck)) {
    k = fe.Find("STIFFNESS");
    m = fe.Find("MASS");
  }
};

Eigen::VectorXd Hz(const Eigen::VectorXd& lambda) {
  return lambda.cwiseMax(0.0).cwiseSqrt() / kTwoPi;
}

TEST(FeMeshReduction, BladeSectorNodeSetsAndBoundary) {
  const Model blade(kMeshes + "blade_sector/coarse/blade_sector.inp");
  ASSERT_NE(blade.k, nullptr);
  ASSERT_NE(blade.m, nullptr);
  EXPECT_EQ(blade.k->rows, 4077);
  ASSERT_NE(blade.fe.FindNodeSet("EXCITATION"), nullptr);
  EXPECT_EQ(blade.fe.FindNodeSet("EXCITATION")->nodes.size(), 1u);
  EXPECT_EQ(blade.fe.FindNodeSet("RESPONSE")->nodes.size(), 1u);
  const BoundarySelection sel = SelectBoundaryDofs(blade.fe, *blade.k, kBladeSets);
  // 27 + 27 contact nodes (the faces' grids) + 2 tip nodes, 3 components each.
  EXPECT_EQ(sel.nodes.size(), 56u);
  EXPECT_EQ(sel.indices.size(), 168u);
  // Only the radial component of the tip nodes:
  const BoundarySelection z = SelectBoundaryDofs(blade.fe, *blade.k, {"RESPONSE"}, {3});
  ASSERT_EQ(z.dofs.size(), 1u);
  EXPECT_EQ(z.dofs[0].component, 3);
  // The clamped root has no DOFs left: asking for it is an error, not an empty boundary.
  EXPECT_THROW(SelectBoundaryDofs(blade.fe, *blade.k, {"ROOT"}), std::invalid_argument);
}

TEST(FeMeshReduction, BladeSectorEigenfrequenciesConvergeToTheFullModel) {
  const Model blade(kMeshes + "blade_sector/coarse/blade_sector.inp");
  const BoundarySelection sel = SelectBoundaryDofs(blade.fe, *blade.k, kBladeSets);
  ModalSolveOptions mo;
  mo.num_modes = 10;
  const ModalSolveResult full = SolveLowestModes(blade.k->real, blade.m->real, mo);
  ASSERT_EQ(full.status, ModalSolveStatus::kSuccess) << full.message;
  const Eigen::VectorXd f_full = Hz(full.lambda);
  // ccx's own eigenvalue run of this mesh (meshes/README.md): 1089.9, 3489.2, 4080.1 Hz.
  EXPECT_NEAR(f_full(0), 1089.9, 0.1);
  EXPECT_NEAR(f_full(1), 3489.2, 0.1);

  std::vector<Eigen::VectorXd> errors;
  for (const double cutoff : {50e3, 100e3}) {
    CraigBamptonOptions opt;
    opt.cutoff_hz = cutoff;
    CraigBamptonSummary s;
    const ReducedModel r = ReduceCraigBampton(blade.k->real, blade.m->real, sel.indices, opt, &s);
    ASSERT_EQ(s.status, CraigBamptonStatus::kSuccess) << s.BriefReport();
    EXPECT_LT(s.checks.Max(), 1e-10) << s.BriefReport();
    ASSERT_GT(s.modes, 0);
    EXPECT_LE(s.frequencies_hz.back(), cutoff);
    const Eigen::VectorXd f_red = Hz(ReducedEigenvalues(r.stiffness, r.mass));
    Eigen::VectorXd e(10);
    int well_below = 0;
    for (int j = 0; j < 10; ++j) {
      e(j) = (f_red(j) - f_full(j)) / f_full(j);
      // Rayleigh-Ritz: the reduced model is stiffer (tolerance: ARPACK and round-off).
      EXPECT_GT(e(j), -1e-9) << "mode " << j + 1;
      if (f_full(j) <= cutoff / 40) {
        ++well_below;
        EXPECT_LT(e(j), 1e-6) << "mode " << j + 1 << " at " << f_full(j) << " Hz, cutoff "
                              << cutoff;
      }
      if (f_full(j) <= cutoff / 4) {
        EXPECT_LT(e(j), 1e-2) << "mode " << j + 1;
      }
    }
    EXPECT_GE(well_below, 1);
    errors.push_back(e);
  }
  // More modes (higher cutoff), smaller error, mode by mode.
  for (int j = 0; j < 10; ++j) EXPECT_LT(errors[1](j), errors[0](j)) << "mode " << j + 1;
}

TEST(FeMeshReduction, BladeSectorStaticBoundaryResponseIsExactInteriorConverges) {
  const Model blade(kMeshes + "blade_sector/coarse/blade_sector.inp");
  const BoundarySelection sel = SelectBoundaryDofs(blade.fe, *blade.k, kBladeSets);
  double previous = 1.0;
  for (const int modes : {5, 20, 80}) {
    CraigBamptonOptions opt;
    opt.num_modes = modes;
    CraigBamptonSummary s;
    const ReducedModel r = ReduceCraigBampton(blade.k->real, blade.m->real, sel.indices, opt, &s);
    ASSERT_EQ(s.status, CraigBamptonStatus::kSuccess);
    const StaticCheckResult st =
        CompareStaticBodyLoad(blade.k->real, blade.m->real, blade.k->row_dofs, r, {0, 0, 9.81});
    ASSERT_TRUE(st.solved) << st.message;
    EXPECT_LT(st.rel_error, 1e-9);  // static condensation is exact on the boundary
    EXPECT_LT(st.interior_rel_error, previous);
    previous = st.interior_rel_error;
  }
  EXPECT_LT(previous, 1e-2);
}

// Closed form of the damper: the hexagonal section (meshes/damper/damper.geo defaults, y-z plane,
// metres) extruded over x in [-L/2, L/2], density 8200 kg/m^3.
struct Section {
  std::vector<std::array<double, 2>> p = {{0.015, 0.0175}, {0.018, 0.0175}, {0.0205, 0.015},
                                          {0.0205, 0.012}, {0.0125, 0.012}, {0.0125, 0.015}};
  // Polygon integrals (Green): area, first and second moments over the section.
  double a = 0, sy = 0, sz = 0, iyy = 0, izz = 0, iyz = 0;
  Section() {
    for (size_t i = 0; i < p.size(); ++i) {
      const auto [y0, z0] = p[i];
      const auto [y1, z1] = p[(i + 1) % p.size()];
      const double c = y0 * z1 - y1 * z0;
      a += c / 2;
      sy += (y0 + y1) * c / 6;
      sz += (z0 + z1) * c / 6;
      iyy += (y0 * y0 + y0 * y1 + y1 * y1) * c / 12;  // integral of y^2
      izz += (z0 * z0 + z0 * z1 + z1 * z1) * c / 12;  // integral of z^2
      iyz += (y0 * z1 + 2 * y0 * z0 + 2 * y1 * z1 + y1 * z0) * c / 24;
    }
    if (a < 0) {  // clockwise vertex order: every integral changes sign
      for (double* v : {&a, &sy, &sz, &iyy, &izz, &iyz}) *v = -*v;
    }
  }
};

TEST(FeMeshReduction, FreeFreeDamperKeepsItsRigidBodyModesAndMassProperties) {
  const Model damper(kMeshes + "damper/coarse/damper.inp");
  ASSERT_NE(damper.k, nullptr);
  const BoundarySelection sel =
      SelectBoundaryDofs(damper.fe, *damper.k, {"CONTACT_LEFT", "CONTACT_RIGHT"});
  CraigBamptonOptions opt;
  opt.num_modes = 10;
  CraigBamptonSummary s;
  const ReducedModel r = ReduceCraigBampton(damper.k->real, damper.m->real, sel.indices, opt, &s);
  ASSERT_EQ(s.status, CraigBamptonStatus::kSuccess) << s.BriefReport();

  // Six zero eigenvalues of the reduced model (the constraint modes carry rigid motion), then
  // elastic ones within a few percent of the full model's first elastic mode.
  const Eigen::VectorXd lam = ReducedEigenvalues(r.stiffness, r.mass);
  for (int j = 0; j < 6; ++j) EXPECT_LT(std::abs(lam(j)), 1e-8 * lam(6)) << "mode " << j + 1;
  ModalSolveOptions mo;
  mo.num_modes = 8;
  const ModalSolveResult full = SolveLowestModes(damper.k->real, damper.m->real, mo);
  ASSERT_EQ(full.status, ModalSolveStatus::kSuccess) << full.message;
  EXPECT_LT(full.shift_used, 0.0);  // singular K: the solver shifted by itself
  EXPECT_LT(std::abs(full.lambda(5)), 1e-8 * full.lambda(6));
  EXPECT_NEAR(Hz(lam)(6) / Hz(full.lambda)(6), 1.0, 0.02);
  EXPECT_GE(lam(6), full.lambda(6) * (1 - 1e-9));

  // Mass properties: full model, reduced model (rigid fields restricted to the boundary) and the
  // closed form agree.
  const Eigen::Vector3d ref(0, 0.0165, 0.0145);
  const Eigen::MatrixXd rfull = RigidBodyModes(damper.fe, damper.k->row_dofs, ref);
  EXPECT_LT((damper.k->real * rfull).cwiseAbs().maxCoeff(),
            1e-9 * damper.k->real.coeffs().cwiseAbs().maxCoeff());
  Eigen::MatrixXd rred = Eigen::MatrixXd::Zero(r.stiffness.rows(), 6);
  for (size_t i = 0; i < sel.indices.size(); ++i) {
    rred.row(static_cast<Eigen::Index>(i)) = rfull.row(sel.indices[i]);
  }
  EXPECT_LT((r.stiffness * rred).cwiseAbs().maxCoeff(), 1e-9 * r.stiffness.cwiseAbs().maxCoeff());
  MassProperties pf = MassPropertiesFromRigidMass(rfull.transpose() * (damper.m->real * rfull));
  MassProperties pr = MassPropertiesFromRigidMass(rred.transpose() * r.mass * rred);
  pf.center += ref;
  pr.center += ref;

  const Section sec;
  const double rho = 8200, length = 0.030;
  const double mass = rho * sec.a * length;
  const Eigen::Vector3d c(0, sec.sy / sec.a, sec.sz / sec.a);
  // Second moments about the centre: section part (y, z) and the x extent L^2/12.
  const double jyy_c = sec.iyy - sec.a * c.y() * c.y();
  const double jzz_c = sec.izz - sec.a * c.z() * c.z();
  const double jyz_c = sec.iyz - sec.a * c.y() * c.z();
  const double xx = length * length / 12.0 * sec.a;  // integral of x^2 over the section * L / L
  Eigen::Matrix3d inertia;
  inertia << jyy_c + jzz_c, 0, 0,  //
      0, xx + jzz_c, -jyz_c,       //
      0, -jyz_c, xx + jyy_c;
  inertia *= rho * length;
  EXPECT_NEAR(mass, 9.2865e-3, 1e-7);  // meshes/README.md
  for (const MassProperties* p : {&pf, &pr}) {
    EXPECT_NEAR(p->mass / mass, 1.0, 1e-10);
    EXPECT_LT((p->center - c).norm(), 1e-10);
    EXPECT_LT((p->inertia_at_center - inertia).cwiseAbs().maxCoeff(), 1e-9 * inertia.maxCoeff());
  }
}

}  // namespace
}  // namespace fricrom
