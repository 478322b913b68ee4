// The condensed harmonic balance against the full one (issue 10): same solutions, exact
// derivatives (central differences), energy balance, and bounds through the same code path.
#include "fricrom/condensed_system.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <memory>
#include <random>
#include <set>
#include <stdexcept>

#include "fricrom/bounds.h"
#include "fricrom/frf.h"
#include "fricrom/hbm_system.h"
#include "fricrom/units.h"
#include "test_models.h"

namespace fricrom {
namespace {

// Each contact as two 1D laws along x and y with kn/2, preload halves and 2μ (as [[interfaces]]
// tangential_directions = 2 builds them): the pair's normal row is shared by the two laws.
void SplitIntoTwoTangentialDirections(Model* model) {
  std::vector<Contact> split;
  for (const Contact& ct : model->contacts) {
    for (int d = 0; d < 2; ++d) {
      Contact half = ct;
      half.name = ct.name + (d ? ".t2" : ".t1");
      half.tangent = d ? Eigen::VectorXd{{0.0, 1.0, 0.0}} : Eigen::VectorXd{{1.0, 0.0, 0.0}};
      half.kn = 0.5 * ct.kn;
      half.kt = 0.5 * ct.kt;
      half.normal_preload = 0.5 * ct.normal_preload;
      half.mu = 2.0 * ct.mu;
      split.push_back(half);
    }
  }
  model->contacts = split;
}

struct Pair {
  Model model;
  HbmOptions options;
};

Pair Baseline(int harmonics = 1) {
  return {testing::LoadBaseline().model, HbmOptions{harmonics, 128}};
}

// A converged full solution at (f, α) and the condensed system's residual at its condensation.
TEST(Condensed, FullSolutionsAreCondensedSolutions) {
  for (int h : {1, 3}) {
    const Pair p = Baseline(h);
    HbmSystem full(p.model, p.options);
    CondensedSystem cond(p.model, p.options);
    for (double f : {250.0, 262.0, 266.0, 270.0}) {
      const Eigen::Vector4d alpha(0.3, -0.7, 1.0, 0.0);
      const FrfPoint sol = SolveAtFrequency(full, alpha, f, Eigen::VectorXd(), FrfOptions{});
      ASSERT_EQ(sol.status, SolverStatus::kConverged) << f;
      const Eigen::VectorXd xc = cond.Condense(sol.x);
      // Through the interface (what verify does with a time integration's harmonics): the same.
      const HarmonicBalance& as_balance = cond;
      EXPECT_EQ(as_balance.FromDofCoefficients(sol.x), xc);
      const HarmonicBalance& full_balance = full;
      EXPECT_EQ(full_balance.FromDofCoefficients(sol.x), sol.x);
      EXPECT_THROW(as_balance.FromDofCoefficients(xc), std::invalid_argument);
      HbmEvaluation e;
      cond.Evaluate(xc, kTwoPi * f, alpha, HbmRequest{}, &e);
      EXPECT_LE(e.residual.norm(), 1e-9 * cond.ResidualScale()) << "H " << h << ", " << f << " Hz";
      const Eigen::VectorXd back = cond.Recover(xc, kTwoPi * f, alpha);
      EXPECT_LE((back - sol.x).norm(), 1e-9 * sol.x.norm()) << "H " << h << ", " << f << " Hz";
      EXPECT_NEAR(cond.Amplitude(xc), full.Amplitude(sol.x), 1e-12 * full.Amplitude(sol.x));
    }
  }
}

// Solved independently (its own stick start, its own Newton), the condensed balance lands on the
// full solution.
TEST(Condensed, CondensedNewtonReproducesTheFullSolution) {
  const Pair p = Baseline();
  HbmSystem full(p.model, p.options);
  CondensedSystem cond(p.model, p.options);
  for (double f : {258.0, 262.0, 270.0}) {
    const Eigen::Vector4d alpha = Eigen::Vector4d::Zero();
    const FrfPoint a = SolveAtFrequency(full, alpha, f, Eigen::VectorXd(), FrfOptions{});
    const FrfPoint b = SolveAtFrequency(cond, alpha, f, Eigen::VectorXd(), FrfOptions{});
    ASSERT_EQ(a.status, SolverStatus::kConverged);
    ASSERT_EQ(b.status, SolverStatus::kConverged);
    EXPECT_NEAR(b.amplitude, a.amplitude, 1e-10 * a.amplitude) << f;
    const Eigen::VectorXd xb = cond.Recover(b.x, kTwoPi * f, alpha);
    EXPECT_LE((xb - a.x).norm(), 1e-9 * a.x.norm()) << f;
  }
}

// Exact derivatives of the condensed residual against central differences, at points with
// stick, slip and lift-off (random perturbations of converged solutions).
TEST(Condensed, DerivativesMatchCentralDifferences) {
  // A light preload (15 N instead of 150 N) makes the contacts lift off near resonance.
  const Pair p{testing::LoadBaseline({{"F0_ref", 15.0}}).model, HbmOptions{2, 128}};
  HbmSystem full(p.model, p.options);
  CondensedSystem cond(p.model, p.options);
  std::mt19937 rng(7);
  std::normal_distribution<double> nd(0.0, 1.0);
  std::set<ContactState> seen;
  for (double f : {240.0, 266.0, 285.0}) {
    const Eigen::Vector4d alpha(0.2, -0.4, 0.6, -0.1);
    const double w = kTwoPi * f;
    const FrfPoint sol = SolveAtFrequency(full, alpha, f, Eigen::VectorXd(), FrfOptions{});
    ASSERT_EQ(sol.status, SolverStatus::kConverged);
    Eigen::VectorXd x = cond.Condense(sol.x);
    for (int i = 0; i < x.size(); ++i) x[i] *= 1.0 + 0.05 * nd(rng);
    HbmEvaluation e;
    HbmRequest all;
    all.jacobian = all.alpha_jacobian = all.omega_derivative = true;
    cond.Evaluate(x, w, alpha, all, &e);
    const double scale = cond.ResidualScale();
    for (int k = 0; k < x.size(); ++k) {
      const double hx = 1e-7 * std::max(x.cwiseAbs().maxCoeff(), 1e-12);
      Eigen::VectorXd xp = x, xm = x;
      xp[k] += hx;
      xm[k] -= hx;
      HbmEvaluation ep, em;
      cond.Evaluate(xp, w, alpha, HbmRequest{}, &ep);
      cond.Evaluate(xm, w, alpha, HbmRequest{}, &em);
      const Eigen::VectorXd fd = (ep.residual - em.residual) / (2 * hx);
      EXPECT_LE((fd - e.jacobian.col(k)).norm(), 1e-5 * std::max(e.jacobian.col(k).norm(), scale))
          << "column " << k << " at " << f << " Hz";
    }
    for (int c = 0; c < 4; ++c) {
      Eigen::Vector4d ap = alpha, am = alpha;
      ap[c] += 1e-6;
      am[c] -= 1e-6;
      HbmEvaluation ep, em;
      cond.Evaluate(x, w, ap, HbmRequest{}, &ep);
      cond.Evaluate(x, w, am, HbmRequest{}, &em);
      const Eigen::VectorXd fd = (ep.residual - em.residual) / 2e-6;
      EXPECT_LE((fd - e.alpha_jacobian.col(c)).norm(), 1e-5 * std::max(fd.norm(), 1e-6 * scale))
          << "alpha " << c << " at " << f << " Hz";
    }
    HbmEvaluation ep, em;
    cond.Evaluate(x, w * (1 + 1e-7), alpha, HbmRequest{}, &ep);
    cond.Evaluate(x, w * (1 - 1e-7), alpha, HbmRequest{}, &em);
    const Eigen::VectorXd fd = (ep.residual - em.residual) / (2e-7 * w);
    EXPECT_LE((fd - e.omega_derivative).norm(), 1e-5 * std::max(fd.norm(), 1e-9 * scale)) << f;
    for (const ContactHistory& hist : cond.ContactHistories(x, w, alpha)) {
      for (ContactState st : hist.states) seen.insert(st);
    }
  }
  // The points exercised every branch of the law: stick, both slip directions, lift-off.
  EXPECT_EQ(seen.size(), 4u);
}

// The matrix-free Jacobian (Linearize) equals the dense one, J v and Jᵀ v, in stick, slip and
// lift-off (light preload), at H = 1, 2 and 3, and where contacts share a normal row.
void ExpectOperatorEqualsDense(const CondensedSystem& cond, const Eigen::VectorXd& x, double w,
                               const Eigen::VectorXd& alpha, unsigned seed) {
  HbmEvaluation e;
  HbmRequest req;
  req.jacobian = true;
  cond.Evaluate(x, w, alpha, req, &e);
  const std::unique_ptr<JacobianOperator> op = cond.Linearize(x, w, alpha);
  ASSERT_NE(op, nullptr);
  std::srand(seed);
  for (int k = 0; k < 3; ++k) {
    const Eigen::VectorXd v = Eigen::VectorXd::Random(x.size());
    Eigen::VectorXd jv, jtv;
    op->Apply(v, false, &jv);
    op->Apply(v, true, &jtv);
    const Eigen::VectorXd ref = e.jacobian * v, ref_t = e.jacobian.transpose() * v;
    EXPECT_LE((jv - ref).norm(), 1e-12 * ref.norm());
    EXPECT_LE((jtv - ref_t).norm(), 1e-12 * ref_t.norm());
  }
}

TEST(Condensed, MatrixFreeJacobianEqualsTheDenseJacobian) {
  const Model light = testing::LoadBaseline({{"F0_ref", 15.0}}).model;
  std::set<ContactState> seen;
  for (int harmonics : {1, 2, 3}) {
    CondensedSystem cond(light, HbmOptions{harmonics, 128});
    for (double f : {240.0, 266.0, 285.0}) {
      const Eigen::Vector4d alpha(0.2, -0.4, 0.6, -0.1);
      const FrfPoint sol = SolveAtFrequency(cond, alpha, f, Eigen::VectorXd(), FrfOptions{});
      ASSERT_EQ(sol.status, SolverStatus::kConverged);
      ExpectOperatorEqualsDense(cond, sol.x, kTwoPi * f, alpha, 3 + harmonics);
      for (const ContactHistory& hist : cond.ContactHistories(sol.x, kTwoPi * f, alpha)) {
        for (ContactState st : hist.states) seen.insert(st);
      }
    }
  }
  EXPECT_EQ(seen.size(), 4u);  // stick, both slip directions, lift-off
  // 12 pairs with two tangential directions each (shared normal rows), from a perturbed start
  // (stuck and slipping pairs mixed) and at the converged state.
  Model strip = testing::ContactStrip(12);
  SplitIntoTwoTangentialDirections(&strip);
  for (int harmonics : {1, 3}) {
    CondensedSystem cond(strip, HbmOptions{harmonics, 64});
    const Eigen::VectorXd alpha = Eigen::VectorXd::LinSpaced(cond.num_contacts(), -0.9, 0.9);
    const double w = kTwoPi * 1000.0;
    ExpectOperatorEqualsDense(cond, 3.0 * cond.StickLinearSolution(w), w, alpha, 11);
    const FrfPoint sol = SolveAtFrequency(cond, alpha, 1000.0, Eigen::VectorXd(), FrfOptions{});
    ASSERT_EQ(sol.status, SolverStatus::kConverged);
    ExpectOperatorEqualsDense(cond, sol.x, w, alpha, 12);
  }
}

// The contact forces of the last (x, α) are reused (CondensedSystem::ContactForces): every
// request in a sequence that revisits points, changes only α or only ω, and asks for more or fewer
// derivatives equals, bit for bit, the same request on a twin system that is made to compute
// anew (it evaluates an unrelated point in between).
TEST(Condensed, ReusedContactForcesEqualFreshOnes) {
  Model strip = testing::ContactStrip(12);
  SplitIntoTwoTangentialDirections(&strip);
  const HbmOptions options{3, 64};
  const CondensedSystem reused(strip, options), fresh(strip, options);
  const double w = kTwoPi * 1000.0;
  const Eigen::VectorXd a1 = Eigen::VectorXd::LinSpaced(reused.num_contacts(), -0.9, 0.9);
  const Eigen::VectorXd a2 = -a1;
  const Eigen::VectorXd x1 = 3.0 * reused.StickLinearSolution(w);  // stuck and slipping pairs
  const Eigen::VectorXd x2 = 0.5 * x1, other = 7.0 * x1;
  HbmRequest plain, jacobian, alpha_jacobian, both;
  jacobian.jacobian = true;
  alpha_jacobian.alpha_jacobian = true;
  both.jacobian = both.alpha_jacobian = true;
  struct Call {
    const Eigen::VectorXd* x;
    double w;
    const Eigen::VectorXd* alpha;
    const HbmRequest* request;  // nullptr: Linearize
  };
  const std::vector<Call> calls = {
      {&x1, w, &a1, &plain},          {&x1, w, &a1, nullptr},     {&x1, w, &a1, &alpha_jacobian},
      {&x1, w, &a1, &plain},          {&x1, 1.1 * w, &a1, &both}, {&x1, w, &a2, &jacobian},
      {&x2, w, &a2, &alpha_jacobian}, {&x2, w, &a2, nullptr},     {&x1, w, &a2, &plain},
      {&x1, w, &a1, &both},           {&x1, w, &a1, &jacobian},   {&x2, w, &a1, &plain}};
  const Eigen::VectorXd v = Eigen::VectorXd::LinSpaced(x1.size(), -1.0, 2.0);
  for (size_t k = 0; k < calls.size(); ++k) {
    const Call& c = calls[k];
    HbmEvaluation unrelated;
    fresh.Evaluate(other, w, a1, plain, &unrelated);
    if (c.request == nullptr) {
      Eigen::VectorXd jv_reused, jv_fresh, jtv_reused, jtv_fresh;
      reused.Linearize(*c.x, c.w, *c.alpha)->Apply(v, false, &jv_reused);
      reused.Linearize(*c.x, c.w, *c.alpha)->Apply(v, true, &jtv_reused);
      fresh.Linearize(*c.x, c.w, *c.alpha)->Apply(v, false, &jv_fresh);
      fresh.Evaluate(other, w, a1, plain, &unrelated);
      fresh.Linearize(*c.x, c.w, *c.alpha)->Apply(v, true, &jtv_fresh);
      EXPECT_EQ(jv_reused, jv_fresh) << "call " << k;
      EXPECT_EQ(jtv_reused, jtv_fresh) << "call " << k;
      continue;
    }
    HbmEvaluation er, ef;
    reused.Evaluate(*c.x, c.w, *c.alpha, *c.request, &er);
    fresh.Evaluate(*c.x, c.w, *c.alpha, *c.request, &ef);
    EXPECT_EQ(er.residual, ef.residual) << "call " << k;
    EXPECT_EQ(er.jacobian, ef.jacobian) << "call " << k;
    EXPECT_EQ(er.alpha_jacobian, ef.alpha_jacobian) << "call " << k;
    ASSERT_EQ(er.residual.size(), x1.size());
    ASSERT_TRUE(er.residual.allFinite());
  }
  // The regimes reuse the forces of the last evaluation as well.
  HbmEvaluation e;
  reused.Evaluate(x1, w, a1, plain, &e);
  fresh.Evaluate(other, w, a1, plain, &e);
  EXPECT_EQ(reused.ContactRegimes(x1, w, a1), fresh.ContactRegimes(x1, w, a1));
  EXPECT_EQ(reused.ContactRegimes(x2, w, a2), fresh.ContactRegimes(x2, w, a2));
}

// Regimes from the condensed unknowns equal those of the recovered histories at solutions, in
// every regime the light-preload baseline reaches.
TEST(Condensed, RegimesFromTheUnknownsEqualTheHistories) {
  CondensedSystem cond(testing::LoadBaseline({{"F0_ref", 15.0}}).model, HbmOptions{1, 128});
  std::set<ContactRegime> seen;
  for (double f : {240.0, 266.0, 285.0}) {
    for (const Eigen::Vector4d& alpha :
         {Eigen::Vector4d(0.2, -0.4, 0.6, -0.1), Eigen::Vector4d(1.0, -1.0, 0.0, 0.9)}) {
      const FrfPoint sol = SolveAtFrequency(cond, alpha, f, Eigen::VectorXd(), FrfOptions{});
      ASSERT_EQ(sol.status, SolverStatus::kConverged);
      const std::vector<ContactRegime> fast = cond.ContactRegimes(sol.x, kTwoPi * f, alpha);
      const std::vector<ContactHistory> hist = cond.ContactHistories(sol.x, kTwoPi * f, alpha);
      ASSERT_EQ(fast.size(), hist.size());
      for (size_t c = 0; c < fast.size(); ++c) {
        EXPECT_EQ(fast[c], hist[c].regime) << f << " Hz, contact " << c;
        seen.insert(fast[c]);
      }
    }
  }
  EXPECT_GE(seen.size(), 2u);
}

// Energy balance at converged condensed solutions: excitation work = viscous + friction.
TEST(Condensed, EnergyBalanceAtConvergedSolutions) {
  const Pair p = Baseline();
  CondensedSystem cond(p.model, p.options);
  for (double f : {262.0, 266.0, 272.0}) {
    const Eigen::Vector4d alpha(1.0, -1.0, 0.5, 0.0);
    const FrfPoint s = SolveAtFrequency(cond, alpha, f, Eigen::VectorXd(), FrfOptions{});
    ASSERT_EQ(s.status, SolverStatus::kConverged);
    const CycleEnergy e = cond.Energies(s.x, kTwoPi * f, alpha);
    EXPECT_NEAR(e.excitation_work, e.viscous_dissipation + e.friction_dissipation(),
                1e-8 * e.excitation_work)
        << f;
  }
}

// Bounds through the condensed balance equal the full ones (both objectives).
TEST(Condensed, BoundsEqualTheFullBounds) {
  const Pair p = Baseline();
  HbmSystem full(p.model, p.options);
  CondensedSystem cond(p.model, p.options);
  for (auto objective : {BoundsOptions::kAmplitude, BoundsOptions::kLossFactor}) {
    BoundsOptions o;
    o.objective = objective;
    const BoundsResult a = ComputeBounds(full, 266.0, o);
    const BoundsResult b = ComputeBounds(cond, 266.0, o);
    ASSERT_TRUE(a.IsUsable() && b.IsUsable()) << a.BriefReport() << "\n" << b.BriefReport();
    EXPECT_NEAR(b.min.amplitude, a.min.amplitude, 1e-8 * a.max.amplitude);
    EXPECT_NEAR(b.max.amplitude, a.max.amplitude, 1e-8 * a.max.amplitude);
  }
}

// Issue 10 acceptance: an FE assembly with 50 contact pairs (300 DOFs): the condensed balance
// (101 unknowns per coefficient) gives the full balance's solution to 1e-10, with exact
// derivatives and energy balance.
TEST(Condensed, TwoTangentialDirectionsShareTheNormalRow) {
  // Each pair of the strip as two 1D laws along x and y with kn/2, preload halves and 2μ (as
  // [[interfaces]] tangential_directions = 2 builds them): the condensed balance has one normal
  // unknown per pair (3 rows, not 4) and still gives the full balance's solution, residual and
  // derivatives.
  Model model = testing::ContactStrip(12);
  SplitIntoTwoTangentialDirections(&model);
  const HbmOptions opt{1, 64};
  HbmSystem full(model, opt);
  CondensedSystem cond(model, opt);
  EXPECT_EQ(cond.num_relative(), 3 * 12);
  EXPECT_EQ(cond.num_unknowns(), 3 * (3 * 12 + 1));
  const Eigen::VectorXd alpha = Eigen::VectorXd::LinSpaced(24, -0.8, 0.8);
  // Both solved well below the 1e-10 compared: Newton's own tolerance is 1e-10 in the residual,
  // which alone leaves differences of that order in x.
  FrfOptions tight;
  tight.newton.residual_tolerance = 1e-13;
  for (double f : {1000.0, 1100.0}) {
    const FrfPoint a = SolveAtFrequency(full, alpha, f, Eigen::VectorXd(), tight);
    const FrfPoint b = SolveAtFrequency(cond, alpha, f, Eigen::VectorXd(), tight);
    ASSERT_EQ(a.status, SolverStatus::kConverged) << f;
    ASSERT_EQ(b.status, SolverStatus::kConverged) << f;
    EXPECT_LE((cond.Recover(b.x, kTwoPi * f, alpha) - a.x).norm(), 1e-10 * a.x.norm()) << f;
    HbmEvaluation j;
    HbmRequest req;
    req.jacobian = req.alpha_jacobian = true;
    cond.Evaluate(b.x, kTwoPi * f, alpha, req, &j);
    const double h = 1e-7 * b.x.cwiseAbs().maxCoeff();
    for (int k = 0; k < cond.num_unknowns(); k += 7) {
      Eigen::VectorXd xp = b.x, xm = b.x;
      xp[k] += h;
      xm[k] -= h;
      HbmEvaluation ep, em;
      cond.Evaluate(xp, kTwoPi * f, alpha, HbmRequest{}, &ep);
      cond.Evaluate(xm, kTwoPi * f, alpha, HbmRequest{}, &em);
      EXPECT_LE(((ep.residual - em.residual) / (2 * h) - j.jacobian.col(k)).norm(),
                1e-5 * std::max(j.jacobian.col(k).norm(), cond.ResidualScale()))
          << "column " << k << " at " << f << " Hz";
    }
    for (int c : {0, 5, 23}) {  // ∂R/∂α against central differences
      Eigen::VectorXd ap = alpha, am = alpha;
      ap[c] += 1e-6;
      am[c] -= 1e-6;
      HbmEvaluation ep, em;
      cond.Evaluate(b.x, kTwoPi * f, ap, HbmRequest{}, &ep);
      cond.Evaluate(b.x, kTwoPi * f, am, HbmRequest{}, &em);
      EXPECT_LE(((ep.residual - em.residual) / 2e-6 - j.alpha_jacobian.col(c)).norm(),
                1e-5 * std::max(j.alpha_jacobian.col(c).norm(), cond.ResidualScale()))
          << "alpha " << c << " at " << f << " Hz";
    }
  }
}

TEST(Condensed, FiftyPairAssemblyMatchesTheFullBalance) {
  const Model model = testing::ContactStrip(50);
  const HbmOptions opt{1, 64};
  HbmSystem full(model, opt);
  CondensedSystem cond(model, opt);
  std::set<ContactState> seen;
  for (double f : {1000.0, 1100.0}) {
    const Eigen::VectorXd alpha = Eigen::VectorXd::LinSpaced(50, -0.9, 0.9);
    const FrfPoint a = SolveAtFrequency(full, alpha, f, Eigen::VectorXd(), FrfOptions{});
    const FrfPoint b = SolveAtFrequency(cond, alpha, f, Eigen::VectorXd(), FrfOptions{});
    ASSERT_EQ(a.status, SolverStatus::kConverged) << f;
    ASSERT_EQ(b.status, SolverStatus::kConverged) << f;
    const Eigen::VectorXd xb = cond.Recover(b.x, kTwoPi * f, alpha);
    EXPECT_LE((xb - a.x).norm(), 1e-10 * a.x.norm()) << f;
    HbmEvaluation e;
    full.Evaluate(xb, kTwoPi * f, alpha, HbmRequest{}, &e);
    EXPECT_LE(e.residual.norm(), 1e-10 * full.ResidualScale()) << f;
    const CycleEnergy en = cond.Energies(b.x, kTwoPi * f, alpha);
    EXPECT_NEAR(en.excitation_work, en.viscous_dissipation + en.friction_dissipation(),
                1e-8 * en.excitation_work);
    // Jacobian columns of a few contacts against central differences.
    HbmEvaluation j;
    HbmRequest req;
    req.jacobian = true;
    cond.Evaluate(b.x, kTwoPi * f, alpha, req, &j);
    for (int k : {0, 1, 37, 60, 100, 150, 250}) {
      const double h = 1e-7 * b.x.cwiseAbs().maxCoeff();
      Eigen::VectorXd xp = b.x, xm = b.x;
      xp[k] += h;
      xm[k] -= h;
      HbmEvaluation ep, em;
      cond.Evaluate(xp, kTwoPi * f, alpha, HbmRequest{}, &ep);
      cond.Evaluate(xm, kTwoPi * f, alpha, HbmRequest{}, &em);
      const Eigen::VectorXd fd = (ep.residual - em.residual) / (2 * h);
      EXPECT_LE((fd - j.jacobian.col(k)).norm(),
                1e-5 * std::max(j.jacobian.col(k).norm(), cond.ResidualScale()))
          << "column " << k << " at " << f << " Hz";
    }
    for (const ContactHistory& hist : cond.ContactHistories(b.x, kTwoPi * f, alpha)) {
      for (ContactState st : hist.states) seen.insert(st);
    }
  }
  EXPECT_GE(seen.size(), 3u);  // stick and both slip directions at least
}

// Harmonic continuation: the H = 1 sibling of an H = 3 system (sharing its receptance) is the
// H = 1 system, and the H = 3 cold solve started from its solution reaches the solution Newton
// finds from the stick start (the same point), in fewer H = 3 iterations (4 against 19-21 on this
// 50-pair strip; on some strips, e.g. 20 or 40 pairs, Newton at H = 3 fails from both starts and
// the solvers' homotopies take over).
TEST(Condensed, HarmonicContinuationStartsFromTheFirstHarmonicSolution) {
  const Model model = testing::ContactStrip(50);
  const Eigen::VectorXd alpha = Eigen::VectorXd::LinSpaced(50, -0.9, 0.9);
  for (ReceptanceMethod method : {ReceptanceMethod::kDense, ReceptanceMethod::kModal}) {
    CondensedSystem h3(model, HbmOptions{3, 64, method});
    CondensedSystem h1(model, HbmOptions{1, 64, method});
    const HarmonicBalance* first = h3.FirstHarmonicBalance();
    ASSERT_NE(first, nullptr);
    EXPECT_EQ(first, h3.FirstHarmonicBalance());  // built once
    EXPECT_EQ(first->harmonics(), 1);
    ASSERT_EQ(first->num_unknowns(), h1.num_unknowns());
    EXPECT_EQ(h1.FirstHarmonicBalance(), nullptr);
    const double w = kTwoPi * 1000.0;
    const Eigen::VectorXd x1 = h1.StickLinearSolution(w) * 1.3;
    HbmEvaluation a, b;
    const HbmRequest all{true, true, true};
    first->Evaluate(x1, w, alpha, all, &a);
    h1.Evaluate(x1, w, alpha, all, &b);
    EXPECT_LE((a.residual - b.residual).norm(), 1e-12 * b.residual.norm());
    EXPECT_LE((a.jacobian - b.jacobian).norm(), 1e-12 * b.jacobian.norm());
    EXPECT_LE((a.alpha_jacobian - b.alpha_jacobian).norm(), 1e-12 * b.alpha_jacobian.norm());
    // Embedding: the H = 1 coefficients in front, zeros for harmonics 2 and 3.
    const Eigen::VectorXd e = h3.EmbedLowerHarmonics(x1, 1);
    EXPECT_EQ(e.head(x1.size()), x1);
    EXPECT_TRUE(e.tail(e.size() - x1.size()).isZero());
    EXPECT_THROW(h3.EmbedLowerHarmonics(e, 1), std::invalid_argument);

    const FrfPoint cont = SolveAtFrequency(h3, alpha, 1000.0, Eigen::VectorXd(), FrfOptions{});
    const FrfPoint p1 = SolveAtFrequency(*first, alpha, 1000.0, Eigen::VectorXd(), FrfOptions{});
    const NewtonOptions newton = FrfOptions{}.newton;
    Eigen::VectorXd x = h3.StickLinearSolution(w), xc = h3.EmbedLowerHarmonics(p1.x, 1);
    const NewtonSummary cold = SolveNewton(HbmAtFrequency(h3, w, alpha), newton, &x);
    const NewtonSummary warm = SolveNewton(HbmAtFrequency(h3, w, alpha), newton, &xc);
    ASSERT_EQ(cont.status, SolverStatus::kConverged);
    ASSERT_TRUE(cold.IsSolutionUsable() && warm.IsSolutionUsable());
    EXPECT_LE((cont.x - x).norm(), 1e-8 * x.norm());
    EXPECT_EQ(cont.iterations, p1.iterations + warm.iterations);  // the route SolveAtFrequency took
    EXPECT_LT(warm.iterations, cold.iterations);
    // Cost in LU work (iterations x unknowns³): the H = 1 iterations are the cheap ones.
    const double n1 = first->num_unknowns(), n3 = h3.num_unknowns();
    EXPECT_LT(p1.iterations * n1 * n1 * n1 + warm.iterations * n3 * n3 * n3,
              0.5 * cold.iterations * n3 * n3 * n3);
  }
  // Loads at a harmonic the sibling would drop: no sibling.
  Model m3 = model;
  HarmonicLoad l3 = m3.loads[0];
  l3.harmonic = 3;
  m3.loads.push_back(l3);
  CondensedSystem with_h3_load(m3, HbmOptions{3, 64});
  EXPECT_EQ(with_h3_load.FirstHarmonicBalance(), nullptr);
  HbmSystem full(m3, HbmOptions{3, 64});
  EXPECT_EQ(full.FirstHarmonicBalance(), nullptr);
}

}  // namespace
}  // namespace fricrom
