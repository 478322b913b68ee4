// The modal route of the condensed balance's receptance against the dense LU route: identical
// for proportional damping, the approximation measured (DampingCoupling) otherwise.
#include "linear/harmonic_receptance.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace fricrom {
namespace {

struct Matrices {
  Eigen::MatrixXd k, m, b;
};

// A small SPD system with a few relative-displacement rows (fixed seed, reproducible).
Matrices MakeSystem(int n, int nr) {
  std::srand(7);
  const Eigen::MatrixXd a = Eigen::MatrixXd::Random(n, n);
  const Eigen::MatrixXd e = Eigen::MatrixXd::Random(n, n);
  Matrices s;
  s.k = 1e6 * (a * a.transpose() + n * Eigen::MatrixXd::Identity(n, n));
  s.m = 0.1 * (e * e.transpose() + n * Eigen::MatrixXd::Identity(n, n));
  s.b = Eigen::MatrixXd::Random(nr, n);
  return s;
}

double RelDiff(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).norm() / std::max(b.norm(), 1e-300);
}

TEST(HarmonicReceptance, ModalEqualsDenseForProportionalDamping) {
  const Matrices s = MakeSystem(14, 6);
  const Eigen::MatrixXd c = 3.0 * s.m + 2e-5 * s.k;  // Rayleigh on (K, M): diagonal in the modes
  HarmonicReceptance dense(s.k, s.m, c, s.b, 3, ReceptanceMethod::kDense);
  HarmonicReceptance modal(s.k, s.m, c, s.b, 3, ReceptanceMethod::kModal);
  EXPECT_LT(modal.DampingCoupling(), 1e-9);
  for (double omega : {50.0, 1234.5, 4000.0}) {
    dense.SetFrequency(omega);
    modal.SetFrequency(omega);
    for (int h = 0; h <= 3; ++h) {
      const int rows = h == 0 ? 14 : 28, rel = h == 0 ? 6 : 12;
      const Eigen::VectorXd f = Eigen::VectorXd::Random(rows), v = Eigen::VectorXd::Random(rel);
      EXPECT_LT(RelDiff(modal.G(h), dense.G(h)), 1e-10) << "h " << h << " omega " << omega;
      EXPECT_LT(RelDiff(modal.Solve(h, f), dense.Solve(h, f)), 1e-10);
      EXPECT_LT(RelDiff(modal.TimesP(h, v), dense.TimesP(h, v)), 1e-10);
      EXPECT_LT(RelDiff(modal.TransposeTimesP(h, f), dense.TransposeTimesP(h, f)), 1e-10);
      EXPECT_LT(RelDiff(modal.PRows(h, 5), dense.PRows(h, 5)), 1e-10);
      EXPECT_LT(RelDiff(modal.DzDomegaTimes(h, f) + Eigen::VectorXd::Ones(rows),
                        dense.DzDomegaTimes(h, f) + Eigen::VectorXd::Ones(rows)),
                1e-10);
    }
  }
}

TEST(HarmonicReceptance, LapackSizedModalEqualsDense) {
  // n = 130 ≥ dense::kLapackMinSize: dgetrf and dsygvd routes, Rayleigh damping.
  const Matrices s = MakeSystem(130, 40);
  const Eigen::MatrixXd c = 3.0 * s.m + 2e-5 * s.k;
  HarmonicReceptance dense(s.k, s.m, c, s.b, 2, ReceptanceMethod::kDense);
  HarmonicReceptance modal(s.k, s.m, c, s.b, 2, ReceptanceMethod::kModal);
  dense.SetFrequency(2500.0);
  modal.SetFrequency(2500.0);
  for (int h = 0; h <= 2; ++h) {
    const Eigen::VectorXd f = Eigen::VectorXd::Random(h == 0 ? 130 : 260);
    EXPECT_LT(RelDiff(modal.G(h), dense.G(h)), 1e-9) << "h " << h;
    EXPECT_LT(RelDiff(modal.Solve(h, f), dense.Solve(h, f)), 1e-9) << "h " << h;
  }
}

// GTimes (complex form for h ≥ 1, BLAS) equals the product with G_h and its transpose, in both
// routes and with non-proportional damping (the structure [[A, B], [−B, A]] holds for any C).
TEST(HarmonicReceptance, GTimesEqualsTheRealBlockProduct) {
  const Matrices s = MakeSystem(130, 50);
  const Eigen::MatrixXd c = 2e-5 * s.k + 1e-3 * Eigen::MatrixXd::Identity(130, 130);
  for (const ReceptanceMethod method : {ReceptanceMethod::kDense, ReceptanceMethod::kModal}) {
    HarmonicReceptance r(s.k, s.m, c, s.b, 3, method);
    r.SetFrequency(1800.0);
    for (int h = 0; h <= 3; ++h) {
      const Eigen::VectorXd v = Eigen::VectorXd::Random(r.G(h).cols());
      Eigen::VectorXd out;
      r.GTimes(h, v, false, &out);
      EXPECT_LT(RelDiff(out, r.G(h) * v), 1e-13) << "h " << h;
      r.GTimes(h, v, true, &out);
      EXPECT_LT(RelDiff(out, r.G(h).transpose() * v), 1e-13) << "h " << h;
    }
  }
}

// The modal route forms Ĝ_h only when needed: until then (the first 32 products at an ω) GTimes
// goes through the modes, equal to the formed product up to round-off, transposed or not; then,
// or when G is read, Ĝ_h is formed and equals the one formed at once, bit for bit.
TEST(HarmonicReceptance, ModalProductsBeforeFormingEqualTheFormedProducts) {
  const Matrices s = MakeSystem(130, 50);
  const Eigen::MatrixXd c = 2e-5 * s.k + 1e-3 * Eigen::MatrixXd::Identity(130, 130);
  HarmonicReceptance lazy(s.k, s.m, c, s.b, 2, ReceptanceMethod::kModal);
  HarmonicReceptance eager(s.k, s.m, c, s.b, 2, ReceptanceMethod::kModal);
  HarmonicReceptance dense(s.k, s.m, c, s.b, 2, ReceptanceMethod::kDense);
  for (double omega : {1800.0, 2600.0}) {
    lazy.SetFrequency(omega);
    eager.SetFrequency(omega);
    dense.SetFrequency(omega);
    for (int h = 1; h <= 2; ++h) {
      ASSERT_EQ(eager.G(h).rows(), 100);  // formed now
      EXPECT_TRUE(eager.GFormed(h));
      EXPECT_TRUE(dense.GFormed(h));
      EXPECT_FALSE(lazy.GFormed(h)) << "h " << h << " omega " << omega;
    }
    // 20 products per harmonic, then 15 more of harmonic 1 (its 33rd forms Ĝ_1).
    for (int k = 0; k < 55; ++k) {
      const int h = k < 40 ? 1 + k % 2 : 1;
      const bool transposed = k % 3 == 0;
      const Eigen::VectorXd v = Eigen::VectorXd::Random(100);
      Eigen::VectorXd a, b;
      lazy.GTimes(h, v, transposed, &a);
      eager.GTimes(h, v, transposed, &b);
      EXPECT_LT(RelDiff(a, b), 1e-13) << "product " << k << " omega " << omega;
      const Eigen::VectorXd ref = transposed ? Eigen::VectorXd(eager.G(h).transpose() * v)
                                             : Eigen::VectorXd(eager.G(h) * v);
      EXPECT_LT(RelDiff(a, ref), 1e-13) << "product " << k << " omega " << omega;
      if (k == 39) {
        EXPECT_FALSE(lazy.GFormed(1));
      }
    }
    EXPECT_TRUE(lazy.GFormed(1));
    EXPECT_FALSE(lazy.GFormed(2));
    EXPECT_EQ(lazy.G(1), eager.G(1));
    EXPECT_EQ(lazy.GComplexColumns(2, {0, 7, 49}), eager.GComplexColumns(2, {0, 7, 49}));
    EXPECT_TRUE(lazy.GFormed(2));
    EXPECT_EQ(lazy.G(2), eager.G(2));
  }
}

// ∂x̃_h/∂ω of x̃_h = Z_h⁻¹ (f_h − B_hᵀ fs) (OmegaDerivative: its relative part and the DOF's
// entries): the modal route (modal coordinates) equals the dense route for proportional damping,
// and each route its own central differences in ω, also with non-proportional damping. The fixed
// loads' responses at the DOF and on the relative rows equal the whole response's.
TEST(HarmonicReceptance, OmegaDerivativeMatchesTheDenseRouteAndDifferences) {
  const Matrices s = MakeSystem(14, 6);
  const int dof = 5;
  const std::vector<Eigen::VectorXd> loads = {
      Eigen::VectorXd::Random(14), Eigen::VectorXd::Random(28), Eigen::VectorXd::Random(28)};
  for (const bool proportional : {true, false}) {
    const Eigen::MatrixXd c =
        proportional ? Eigen::MatrixXd(3.0 * s.m + 2e-5 * s.k)
                     : Eigen::MatrixXd(2e-5 * s.k + 1e-3 * Eigen::MatrixXd::Identity(14, 14));
    std::vector<HarmonicReceptance> routes;
    routes.emplace_back(s.k, s.m, c, s.b, 2, ReceptanceMethod::kDense);
    routes.emplace_back(s.k, s.m, c, s.b, 2, ReceptanceMethod::kModal);
    for (HarmonicReceptance& r : routes) r.SetFixedLoads(loads, dof);
    for (double omega : {1234.5, 4000.0}) {
      for (int h = 0; h <= 2; ++h) {
        const Eigen::VectorXd fs = Eigen::VectorXd::Random(h == 0 ? 6 : 12);
        std::vector<Eigen::VectorXd> rel(2), at(2);
        for (int k = 0; k < 2; ++k) {
          HarmonicReceptance& r = routes[k];
          r.SetFrequency(omega);
          r.OmegaDerivative(h, fs, &rel[k], &at[k]);
          const Eigen::VectorXd whole = r.LoadResponse(h);
          EXPECT_LT(RelDiff(r.LoadRelative(h), r.Relative(h, whole)), 1e-12);
          const Eigen::VectorXd at_dof = h == 0 ? Eigen::VectorXd::Constant(1, whole[dof])
                                                : Eigen::VectorXd{{whole[dof], whole[14 + dof]}};
          EXPECT_LT(RelDiff(r.LoadResponseAtDof(h), at_dof), 1e-12);
          // Central differences of B x̃ and x̃(dof) in ω.
          const double dw = 1e-6 * omega;
          std::vector<Eigen::VectorXd> rel_pm(2), at_pm(2);
          for (int side = 0; side < 2; ++side) {
            r.SetFrequency(omega + (side == 0 ? dw : -dw));
            rel_pm[side] = r.LoadRelative(h) - r.G(h) * fs;
            at_pm[side] = r.LoadResponseAtDof(h) - r.DofPRows(h) * fs;
          }
          r.SetFrequency(omega);
          const Eigen::VectorXd fd_rel = (rel_pm[0] - rel_pm[1]) / (2 * dw);
          const Eigen::VectorXd fd_at = (at_pm[0] - at_pm[1]) / (2 * dw);
          if (h == 0) {
            EXPECT_EQ(rel[k], Eigen::VectorXd::Zero(6));
            EXPECT_EQ(at[k], Eigen::VectorXd::Zero(1));
            continue;
          }
          const double scale = rel_pm[0].norm() / omega;  // |∂/∂ω| ~ |x̃|/ω
          EXPECT_LT((rel[k] - fd_rel).norm(), 1e-6 * std::max(fd_rel.norm(), scale))
              << "route " << k << " h " << h << " omega " << omega;
          EXPECT_LT((at[k] - fd_at).norm(), 1e-6 * std::max(fd_at.norm(), scale))
              << "route " << k << " h " << h << " omega " << omega;
        }
        if (proportional && h > 0) {
          EXPECT_LT(RelDiff(rel[1], rel[0]), 1e-9) << "h " << h << " omega " << omega;
          EXPECT_LT(RelDiff(at[1], at[0]), 1e-9) << "h " << h << " omega " << omega;
        }
      }
    }
  }
}

TEST(HarmonicReceptance, FixedLoadResponsesFollowTheFrequency) {
  // The per-ω cache equals fresh solves, also after the loads are set before any frequency and
  // after a change of frequency.
  const Matrices s = MakeSystem(10, 4);
  const Eigen::MatrixXd c = 1e-4 * s.k;
  for (ReceptanceMethod m : {ReceptanceMethod::kDense, ReceptanceMethod::kModal}) {
    HarmonicReceptance r(s.k, s.m, c, s.b, 2, m);
    std::vector<Eigen::VectorXd> loads = {Eigen::VectorXd::Random(10), Eigen::VectorXd(),
                                          Eigen::VectorXd::Random(20)};
    r.SetFixedLoads(loads, 3);
    for (double omega : {300.0, 4100.0}) {
      r.SetFrequency(omega);
      for (int h = 0; h <= 2; ++h) {
        const Eigen::VectorXd f = loads[h].size() ? loads[h] : Eigen::VectorXd::Zero(20);
        const Eigen::VectorXd x = r.Solve(h, f);
        EXPECT_LT(RelDiff(r.LoadResponse(h) + Eigen::VectorXd::Ones(x.size()),
                          x + Eigen::VectorXd::Ones(x.size())),
                  1e-14);
        EXPECT_LT(RelDiff(r.LoadRelative(h) + Eigen::VectorXd::Ones(r.LoadRelative(h).size()),
                          r.Relative(h, x) + Eigen::VectorXd::Ones(r.LoadRelative(h).size())),
                  1e-14);
        EXPECT_LT(RelDiff(r.DofPRows(h), r.PRows(h, 3)), 1e-14);
      }
    }
    EXPECT_THROW(r.SetFixedLoads(loads, 10), std::invalid_argument);      // DOF out of range
    EXPECT_THROW(r.SetFixedLoads({loads[0]}, 3), std::invalid_argument);  // one per harmonic
  }
}

// SetFrequency(ω, H) forms only h ≤ H (a system with fewer harmonics sharing the receptance):
// what it forms equals the full formation bit for bit, and a harmonic not formed at the current
// ω - never, or at an earlier ω - cannot be read.
TEST(HarmonicReceptance, FormsOnlyTheHarmonicsAskedFor) {
  const Matrices s = MakeSystem(12, 5);
  const Eigen::MatrixXd c = 1e-4 * s.k;
  for (ReceptanceMethod m : {ReceptanceMethod::kDense, ReceptanceMethod::kModal}) {
    HarmonicReceptance all(s.k, s.m, c, s.b, 3, m), part(s.k, s.m, c, s.b, 3, m);
    const std::vector<Eigen::VectorXd> loads = {Eigen::VectorXd::Random(12), Eigen::VectorXd(),
                                                Eigen::VectorXd(), Eigen::VectorXd::Random(24)};
    all.SetFixedLoads(loads, 2);
    part.SetFixedLoads(loads, 2);
    EXPECT_THROW(part.G(0), std::logic_error);  // nothing formed yet
    HarmonicReceptance no_loads(s.k, s.m, c, s.b, 3, m);
    no_loads.SetFrequency(700.0);
    Eigen::VectorXd rel, at;
    EXPECT_THROW(no_loads.LoadResponse(1), std::logic_error);
    EXPECT_THROW(no_loads.OmegaDerivative(1, Eigen::VectorXd::Zero(10), &rel, &at),
                 std::logic_error);
    const Eigen::VectorXd v = Eigen::VectorXd::Random(10);
    for (double omega : {700.0, 2300.0}) {
      all.SetFrequency(omega);
      part.SetFrequency(omega, 1);
      for (int h = 0; h <= 1; ++h) {
        EXPECT_EQ(part.G(h), all.G(h)) << "h " << h << " omega " << omega;
        EXPECT_EQ(part.LoadResponse(h), all.LoadResponse(h));
        EXPECT_EQ(part.DofPRows(h), all.DofPRows(h));
      }
      Eigen::VectorXd a, b;
      part.GTimes(1, v, false, &a);
      all.GTimes(1, v, false, &b);
      EXPECT_EQ(a, b);
      // Harmonics 2 and 3: never formed (first ω) or formed at the earlier ω (second).
      EXPECT_THROW(part.G(2), std::logic_error);
      EXPECT_THROW(part.LoadResponse(3), std::logic_error);
      EXPECT_THROW(part.GTimes(3, Eigen::VectorXd::Zero(10), false, &a), std::logic_error);
      EXPECT_THROW(part.Solve(2, Eigen::VectorXd::Zero(24)), std::logic_error);
      part.SetFrequency(omega);
      for (int h = 2; h <= 3; ++h) {
        EXPECT_EQ(part.G(h), all.G(h)) << "h " << h << " omega " << omega;
        EXPECT_EQ(part.LoadResponse(h), all.LoadResponse(h));
      }
    }
  }
}

TEST(HarmonicReceptance, TransposeIsTheAdjointOfP) {
  // gᵀ (P v) = (Pᵀ g)ᵀ v in both routes, with non-proportional damping.
  const Matrices s = MakeSystem(10, 4);
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(10, 10);
  c(0, 0) = 50.0;
  c(3, 3) = 20.0;
  for (ReceptanceMethod m : {ReceptanceMethod::kDense, ReceptanceMethod::kModal}) {
    HarmonicReceptance r(s.k, s.m, c, s.b, 2, m);
    r.SetFrequency(900.0);
    for (int h = 0; h <= 2; ++h) {
      const Eigen::VectorXd g = Eigen::VectorXd::Random(h == 0 ? 10 : 20);
      const Eigen::VectorXd v = Eigen::VectorXd::Random(h == 0 ? 4 : 8);
      const double lhs = g.dot(r.TimesP(h, v)), rhs = r.TransposeTimesP(h, g).dot(v);
      EXPECT_NEAR(lhs, rhs, 1e-12 * std::abs(lhs) + 1e-300);
    }
  }
}

TEST(HarmonicReceptance, NonProportionalDampingIsReportedAndStaysClose) {
  const Matrices s = MakeSystem(12, 5);
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(12, 12);
  c(0, 0) = 80.0;  // one grounded dashpot: couples the modes
  HarmonicReceptance dense(s.k, s.m, c, s.b, 1, ReceptanceMethod::kDense);
  HarmonicReceptance modal(s.k, s.m, c, s.b, 1, ReceptanceMethod::kModal);
  EXPECT_GT(modal.DampingCoupling(), 0.01);
  // Away from resonances the light damping hardly matters: the two routes agree closely.
  dense.SetFrequency(10.0);
  modal.SetFrequency(10.0);
  EXPECT_LT(RelDiff(modal.G(1), dense.G(1)), 1e-3);
  EXPECT_LT(RelDiff(modal.G(0), dense.G(0)), 1e-12);  // static: damping plays no part
}

TEST(HarmonicReceptance, ModalRouteRefusesASingularMassWithAClearMessage) {
  Matrices s = MakeSystem(8, 3);
  s.m.row(7).setZero();
  s.m.col(7).setZero();  // a massless DOF
  const Eigen::MatrixXd c = Eigen::MatrixXd::Zero(8, 8);
  try {
    HarmonicReceptance r(s.k, s.m, c, s.b, 1, ReceptanceMethod::kModal);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("not positive definite"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("dense"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(HarmonicReceptance(s.k, s.m, c, s.b, 1, ReceptanceMethod::kDense));
}

}  // namespace
}  // namespace fricrom
