// The coarse FE cascade (meshes/cascade3/coarse.toml): three reduced blade sectors and two wedge
// dampers joined by node-to-node interfaces. Checked against the mesh geometry
// (meshes/README.md), the damper's mass and the interface rules (docs/case-files.md).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "app/cli_test_util.h"
#include "fricrom/balance.h"
#include "fricrom/bounds.h"
#include "fricrom/case_file.h"
#include "fricrom/frf.h"

namespace fricrom {
namespace {

namespace fs = std::filesystem;
const fs::path kDir = fs::path(FRICROM_SOURCE_DIR) / "meshes/cascade3";
const double kFaceArea = 1.0606601717798e-4;  // contact strip 0.03 x 0.0025*sqrt(2) [m^2]
const double kDamperMass = 9.2865e-3;         // [kg], meshes/README.md

// The case with one text replacement, written next to the original (relative paths hold).
class CascadeVariant : public ::testing::Test {
 protected:
  Case Load(const std::string& from, const std::string& to, size_t count = 1) {
    std::string text = testing::ReadFile(kDir / "coarse.toml");
    size_t at = 0;
    for (size_t i = 0; i < count; ++i, at += to.size()) {
      at = text.find(from, at);
      if (at == std::string::npos) throw std::runtime_error("variant: '" + from + "' not found");
      text.replace(at, from.size(), to);
    }
    path_ = kDir / ("test-variant-" + std::to_string(getpid()) + ".toml");
    std::ofstream(path_) << text;
    return LoadCase(path_.string());
  }
  void TearDown() override {
    if (!path_.empty()) fs::remove(path_);
  }
  fs::path path_;
};

// modal_damping_basis = "component" (coarse.toml) damps the blades' own modes
// (ComponentModalDamping); "fixed-interface" damps the CB modes only; an unknown basis is an error
// naming the key.
TEST_F(CascadeVariant, ComponentDampingBasisChangesOnlyTheDamping) {
  const Case component = LoadCase((kDir / "coarse.toml").string());
  const Case fixed = Load("modal_damping = 0.002, modal_damping_basis = \"component\" }",
                          "modal_damping = 0.002, modal_damping_basis = \"fixed-interface\" }", 3);
  ASSERT_EQ(component.model.damping.rows(), fixed.model.damping.rows());
  EXPECT_TRUE(component.model.stiffness == fixed.model.stiffness);
  EXPECT_TRUE(component.model.mass == fixed.model.mass);
  EXPECT_GT((component.model.damping - fixed.model.damping).norm(),
            0.1 * fixed.model.damping.norm());
  EXPECT_LT((component.model.damping - component.model.damping.transpose()).norm(),
            1e-12 * component.model.damping.norm());
  try {
    Load("modal_damping_basis = \"component\" }", "modal_damping_basis = \"modal\" }");
    FAIL() << "an unknown basis was accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("modal_damping_basis"), std::string::npos) << e.what();
  }
}

// coarse_fixed_interface_damping.toml is coarse.toml with its name and the blades' damping basis
// changed, nothing else (its header comment aside), so that what the docs measured on it (the
// case's damping until 2026-11-27) stays reproducible and comparable.
TEST(Cascade, FixedInterfaceVariantDiffersOnlyInTheDamping) {
  std::string coarse = testing::ReadFile(kDir / "coarse.toml");
  const std::string variant = testing::ReadFile(kDir / "coarse_fixed_interface_damping.toml");
  const auto replace_all = [](std::string* t, const std::string& from, const std::string& to) {
    int n = 0;
    for (size_t at = t->find(from); at != std::string::npos; at = t->find(from, at + to.size())) {
      t->replace(at, from.size(), to);
      ++n;
    }
    return n;
  };
  EXPECT_EQ(replace_all(&coarse, "name = \"cascade3-coarse\"",
                        "name = \"cascade3-coarse-fixed-interface-damping\""),
            1);
  EXPECT_EQ(replace_all(&coarse, "modal_damping = 0.002, modal_damping_basis = \"component\" }",
                        "modal_damping = 0.002 }"),
            3);
  const size_t body = variant.find("# Three coarse FE blade sectors");
  ASSERT_NE(body, std::string::npos);
  EXPECT_EQ(variant.substr(body), coarse);
  EXPECT_EQ(LoadCase((kDir / "coarse_fixed_interface_damping.toml").string()).name,
            "cascade3-coarse-fixed-interface-damping");
}

TEST(Cascade, InterfacesPairAllNodesWithFramesAndAreaStiffness) {
  const Case c = LoadCase((kDir / "coarse.toml").string());
  ASSERT_EQ(c.model.contacts.size(), 216u);     // 4 faces x 27 pairs x 2 tangential directions
  EXPECT_EQ(c.model.num_alpha(), 216);          // one α per pair and direction
  EXPECT_EQ(c.model.num_contact_pairs(), 108);  // the two directions of a pair count once
  const double k_area = c.parameters.at("k_area"), mu = c.parameters.at("mu");
  for (const std::string face : {"d1L.", "d1R.", "d2L.", "d2R."}) {
    double kn = 0, kt1 = 0;
    int n = 0;
    for (const Contact& ct : c.model.contacts) {
      if (ct.name.rfind(face, 0) != 0) continue;
      ++n;
      kn += ct.kn;  // halves of the pair's kn on the two directions
      if (ct.name.ends_with(".t1")) kt1 += ct.kt;
      EXPECT_NEAR(ct.mu, 2.0 * mu, 1e-15) << ct.name;  // T_i <= (2 mu)(N/2) = mu N
      // Damper faces (A side): CONTACT_LEFT normal (0,-1,1)/sqrt2, CONTACT_RIGHT (0,1,1)/sqrt2.
      const double sy = face[2] == 'L' ? -1.0 : 1.0;
      EXPECT_NEAR(ct.normal[0], 0.0, 1e-9) << ct.name;
      EXPECT_NEAR(ct.normal[1], sy / std::numbers::sqrt2, 1e-9) << ct.name;
      EXPECT_NEAR(ct.normal[2], 1.0 / std::numbers::sqrt2, 1e-9) << ct.name;
      EXPECT_NEAR(ct.tangent.dot(ct.normal), 0.0, 1e-12) << ct.name;
      const double axial = ct.name.ends_with(".t2") ? 1.0 : 0.0;  // t2 = n x t1 = +-x
      EXPECT_NEAR(std::abs(ct.tangent[0]), axial, 1e-9) << ct.name;
    }
    EXPECT_EQ(n, 54) << face;
    EXPECT_NEAR(kn, k_area * kFaceArea, 1e-9 * k_area * kFaceArea) << face;
    EXPECT_NEAR(kt1, k_area * kFaceArea, 1e-9 * k_area * kFaceArea) << face;
  }
}

// Contact-state maps and interface seeds: every contact knows its interface and where its pair
// sits; the second damper's faces are the first's moved by the pitch; α groups per interface and
// direction.
TEST(Cascade, ContactsKnowTheirInterfacePositionAndSeedGroup) {
  const Case c = LoadCase((kDir / "coarse.toml").string());
  ASSERT_EQ(c.interface_names, (std::vector<std::string>{"d1L", "d1R", "d2L", "d2R"}));
  ASSERT_EQ(c.contact_positions.cols(), 216);
  ASSERT_EQ(c.contact_interface.size(), 216u);
  ASSERT_EQ(c.alpha_interface.size(), 216u);
  const double pitch = c.parameters.at("pitch");
  for (int k = 0; k < 216; ++k) {
    const int i = c.contact_interface[k];
    ASSERT_GE(i, 0);
    EXPECT_EQ(c.model.contacts[k].name.rfind(c.interface_names[i] + ".", 0), 0u) << k;
    EXPECT_EQ(c.alpha_interface[k], 2 * i + (k % 2)) << k;  // .t1, .t2 alternate
    if (k % 2 == 1) {
      EXPECT_EQ(c.contact_positions.col(k), c.contact_positions.col(k - 1)) << k;  // one pair
    }
    if (i >= 2) {  // damper 2 = damper 1 moved by the pitch along +y
      const Eigen::Vector3d d = c.contact_positions.col(k) - c.contact_positions.col(k - 108);
      EXPECT_NEAR((d - Eigen::Vector3d(0.0, pitch, 0.0)).norm(), 0.0, 1e-12) << k;
    }
  }
}

TEST(Cascade, CentrifugalLoadOnEachDamperIsItsMassTimesTheAcceleration) {
  const Case c = LoadCase((kDir / "coarse.toml").string(), {{"gamma", 0.2}});
  const double omega = 2.0 * std::numbers::pi * c.parameters.at("rpm") / 60.0;
  const double a = omega * omega * c.parameters.at("radius");
  // A rigid radial (z) translation of a CB body moves its physical z DOFs by 1 and its modal DOFs
  // by 0: the static load's work on it is the resultant m a.
  Eigen::VectorXd f0 = Eigen::VectorXd::Zero(c.model.num_dofs());
  for (const HarmonicLoad& l : c.model.loads) {
    if (l.harmonic == 0) f0 += l.cos;
  }
  for (int d = 1; d <= 2; ++d) {
    double fz = 0, fx = 0;
    for (int i = 0; i < c.model.num_dofs(); ++i) {
      const std::string& name = c.model.dof_names[i];
      if (name.rfind("damper" + std::to_string(d) + ".", 0) != 0) continue;
      if (name.ends_with(".z")) fz += f0[i];
      if (name.ends_with(".x")) fx += f0[i];
    }
    const double expected = kDamperMass * a * (d == 1 ? 0.8 : 1.2);
    EXPECT_NEAR(fz, expected, 1e-6 * expected) << "damper" << d;
    EXPECT_NEAR(fx, 0.0, 1e-9 * expected) << "damper" << d;
  }
}

TEST_F(CascadeVariant, OneAlphaPerInterfaceAndDirection) {
  const Case c = Load("mu = \"mu\"\n", "mu = \"mu\"\nalpha = \"interface\"\n", 4);
  EXPECT_EQ(c.model.contacts.size(), 216u);
  EXPECT_EQ(c.model.num_alpha(), 8);
  EXPECT_EQ(c.alpha_interface, (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7}));
}

TEST_F(CascadeVariant, BadTangentialDirectionsNamesTheKey) {
  try {
    Load("tangential_directions = 2", "tangential_directions = 3");
    FAIL() << "expected a CaseError";
  } catch (const CaseError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("interfaces[0].tangential_directions"), std::string::npos) << m;
    EXPECT_NE(m.find(path_.string()), std::string::npos) << m;
  }
}

// Interfaces the analysis cannot represent are errors naming the key (they used to give numbers:
// the same sets paired twice doubled the contacts, a zero slip direction, a duplicate name).
TEST_F(CascadeVariant, InterfacesWithoutMeaningAreErrors) {
  const auto error = [&](const std::string& from, const std::string& to) {
    try {
      Load(from, to);
    } catch (const CaseError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  std::string e = error("name = \"d1R\"", "name = \"d1L\"");
  EXPECT_NE(e.find("interfaces[1].name': duplicate interface name"), std::string::npos) << e;
  e = error(
      "a = { body = \"damper1\", set = \"CONTACT_RIGHT\" }\nb = { body = \"blade2\", set = "
      "\"CONTACT_LEFT\" }",
      "a = { body = \"blade1\", set = \"CONTACT_RIGHT\" }\nb = { body = \"damper1\", set = "
      "\"CONTACT_LEFT\" }");
  EXPECT_NE(e.find("pairs the same sets as interfaces[0]"), std::string::npos) << e;
  e = error("b = { body = \"blade1\", set = \"CONTACT_RIGHT\" }",
            "b = { body = \"damper1\", set = \"CONTACT_LEFT\" }");
  EXPECT_NE(e.find("side a and side b are the same set"), std::string::npos) << e;
  e = error("set = \"RESPONSE\"", "set = \"RESPONS\"");
  EXPECT_NE(e.find("body 'blade2' has no node set 'RESPONS'"), std::string::npos) << e;
  e = error("set = \"RESPONSE\"", "set = \"CONTACT_LEFT\"");
  EXPECT_NE(e.find("set 'CONTACT_LEFT' of body 'blade2' has 27 nodes"), std::string::npos) << e;
  e = error("kn_per_area = \"k_area\"", "kn_per_area = 1e300");
  EXPECT_NE(
      e.find("interfaces[0].kn_per_area': a contact stiffness of 1e+300 is not representable"),
      std::string::npos)
      << e;
  e = error("slip_direction = [0.0, 1.0, 0.0]", "slip_direction = [0.0, 0.0, 0.0]");
  EXPECT_NE(e.find("interfaces[0].slip_direction': expected a non-zero vector"), std::string::npos)
      << e;
}

TEST_F(CascadeVariant, UnpairableFacesListTheUnmatchedNodes) {
  // Damper 2 left in sector 1's position: its faces no longer meet blades 2 and 3.
  try {
    Load("damper_mesh.inp\"\ntranslate = [0.0, \"pitch\", 0.0]", "damper_mesh.inp\"");
    FAIL() << "expected a CaseError";
  } catch (const CaseError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("interfaces[2]"), std::string::npos) << m;
    EXPECT_NE(m.find("no partner within the tolerance"), std::string::npos) << m;
  }
}

TEST(Cascade, ConvergesAtOneFrequencyInFullStickWithModalAndDenseReceptance) {
  const Case c = LoadCase((kDir / "coarse.toml").string());
  EXPECT_EQ(c.analysis.receptance, ReceptanceMethod::kModal);
  double amp[2] = {0, 0};
  for (ReceptanceMethod m : {ReceptanceMethod::kModal, ReceptanceMethod::kDense}) {
    const auto b = MakeBalance(c.model, HbmOptions{1, 64, m}, BalanceKind::kCondensed);
    const Eigen::VectorXd alpha = Eigen::VectorXd::Zero(b->num_alpha());
    const std::vector<FrfPoint> r = SolveAtFrequencies(*b, alpha, {1000.0}, FrfOptions{});
    ASSERT_EQ(r.size(), 1u);
    EXPECT_EQ(r[0].status, SolverStatus::kConverged) << r[0].message;
    amp[m == ReceptanceMethod::kModal ? 0 : 1] = r[0].amplitude;
  }
  EXPECT_GT(amp[0], 0.0);
  // Modal damping only on the blades' fixed-interface modes: close to proportional here.
  EXPECT_NEAR(amp[0], amp[1], 1e-3 * amp[1]);
}

// The coarse cascade's condensed balance at H = 1, 64 samples, modal receptance.
std::unique_ptr<HarmonicBalance> CoarseBalanceAtH1() {
  const Case c = LoadCase((kDir / "coarse.toml").string());
  return MakeBalance(c.model, HbmOptions{1, 64, ReceptanceMethod::kModal}, BalanceKind::kCondensed);
}

// Bounds without the sample check and with no run abandoned as dominated: every run ends by its
// own stopping tests.
BoundsOptions EveryRunToItsEnd() {
  BoundsOptions o;
  o.check_samples = 0;
  o.stop_dominated_runs = false;
  return o;
}

// At 1000 Hz the maximum response is the full-stick one, a KKT point at the first seed; the run
// maximising from a lift-off seed crawls along kinks for ~100 iterations towards a lower local
// maximum. Stopping it as dominated leaves both bounds as they are.
TEST(Cascade, DominatedRunsAreAbandonedWithoutChangingTheBounds) {
  const auto b = CoarseBalanceAtH1();
  BoundsOptions o = EveryRunToItsEnd();
  const BoundsResult all = ComputeBounds(*b, 1000.0, o);
  o.stop_dominated_runs = true;
  const BoundsResult cut = ComputeBounds(*b, 1000.0, o);
  ASSERT_TRUE(all.IsUsable() && cut.IsUsable()) << all.BriefReport() << cut.BriefReport();
  EXPECT_EQ(all.runs_abandoned, 0);
  EXPECT_GE(cut.runs_abandoned, 1);
  EXPECT_EQ(cut.min_failures + cut.max_failures, all.min_failures + all.max_failures);
  EXPECT_NEAR(cut.min.amplitude, all.min.amplitude, 1e-12 * all.max.amplitude);
  EXPECT_NEAR(cut.max.amplitude, all.max.amplitude, 1e-12 * all.max.amplitude);
  EXPECT_GT(cut.robustness(), 0.0);
}

// The curve's neighbour starts (ImproveBounds) compare their runs with the bounds they are given
// as well: the run maximising from the solution at α = ½·1 (not a KKT point there, it crawls
// towards a lower local maximum) cannot reach the full-stick maximum held at 1000 Hz and is
// stopped, where with its own start as the only reference it ran to its end. The bounds are
// the same either way.
TEST(Cascade, RunsFromKnownSolutionsStopWhenTheyCannotReachTheBoundsHeld) {
  const auto b = CoarseBalanceAtH1();
  BoundsOptions o = EveryRunToItsEnd();
  o.stop_dominated_runs = true;
  const BoundsResult held = ComputeBounds(*b, 1000.0, o);
  ASSERT_TRUE(held.IsUsable()) << held.BriefReport();
  const Eigen::VectorXd half = Eigen::VectorXd::Constant(b->num_alpha(), 0.5);
  const FrfPoint start = SolveAtFrequency(*b, half, 1000.0, Eigen::VectorXd(), FrfOptions{});
  ASSERT_EQ(start.status, SolverStatus::kConverged);
  ASSERT_LT(start.amplitude, held.max.amplitude);
  const std::vector<KnownSolution> known = {{start.x, half, false, true}};
  BoundsResult to_end = held, cut = held;
  o.stop_dominated_runs = false;
  ImproveBounds(*b, 1000.0, o, known, &to_end);
  o.stop_dominated_runs = true;
  ImproveBounds(*b, 1000.0, o, known, &cut);
  EXPECT_EQ(to_end.optimizer_runs - held.optimizer_runs, 1);
  EXPECT_EQ(cut.optimizer_runs - held.optimizer_runs, 1);
  EXPECT_EQ(to_end.runs_abandoned, held.runs_abandoned);
  EXPECT_EQ(cut.runs_abandoned, held.runs_abandoned + 1);
  EXPECT_EQ(to_end.max.amplitude, held.max.amplitude);
  EXPECT_EQ(cut.max.amplitude, held.max.amplitude);
  EXPECT_EQ(cut.min.amplitude, held.min.amplitude);
}

// BoundsOptions::dominated_by_earlier_runs: at 1103.06 Hz (H = 1, seeds 0 and -0.5·1, no sample
// check) the minimum run from -0.5·1 crawls towards 2.447e-5 m, a local minimum 26x above the
// 9.486e-7 m the run from 0 reached before it; measured against that run it is stopped. Without
// the rule (every run against the seeds' KKT starts only) the same two seeds give y_min
// 9.48589e-7 m and y_max 4.16742e-4 m with no run abandoned, in twice the time (11.2 against
// 5.8 s, 2026-12-01) -- the reference values here, so that the test runs one search.
TEST(Cascade, RunsDominatedByAnEarlierSeedsBoundAreAbandoned) {
  const auto b = CoarseBalanceAtH1();
  BoundsOptions o;
  o.check_samples = 0;
  ASSERT_TRUE(o.stop_dominated_runs && o.dominated_by_earlier_runs);  // the defaults
  const int n = b->num_alpha();
  o.alpha_seeds = {Eigen::VectorXd::Zero(n), Eigen::VectorXd::Constant(n, -0.5)};
  const BoundsResult r = ComputeBounds(*b, 1103.0612244897959, o);
  ASSERT_TRUE(r.IsUsable()) << r.BriefReport();
  EXPECT_GE(r.runs_abandoned, 1) << r.BriefReport();
  EXPECT_EQ(r.min.seed, 0);
  EXPECT_NEAR(r.min.amplitude, 9.48589e-7, 1e-4 * 9.48589e-7);
  EXPECT_NEAR(r.max.amplitude, 4.16742e-4, 1e-4 * 4.16742e-4);
}

// The reduced-space runs' stationarity test (BoundsOptions::stationary_change; the harmonic
// ladder's refinement uses refinement_stationary_change) only decides where a monotone run stops:
// a looser one ends the same path on an earlier iterate. At 1000 Hz the run maximising from the
// seed +0.5 climbs by ever smaller steps (179 iterations at the default 1e-7, 18 at 1e-4: the
// tighter reference here, to keep the test short under the sanitizers); counting a change of 1e-3
// per iteration as none it stops after a few, below the tighter run's maximum and within 1 %.
TEST(Cascade, LooserStationarityTestStopsEarlierOnTheSamePath) {
  const auto b = CoarseBalanceAtH1();
  BoundsOptions o = EveryRunToItsEnd();
  o.line_search_memory = 1;  // monotone: one path, whatever the test
  o.alpha_seeds = {Eigen::VectorXd::Constant(b->num_alpha(), 0.5)};
  o.stationary_change = 1e-4;
  const BoundsResult tight = ComputeBounds(*b, 1000.0, o);
  o.stationary_change = 1e-3;
  const BoundsResult loose = ComputeBounds(*b, 1000.0, o);
  ASSERT_TRUE(tight.max.IsUsable() && loose.max.IsUsable())
      << tight.BriefReport() << loose.BriefReport();
  ASSERT_GE(tight.max.iterations, 10) << "the tighter run must climb for this test";
  EXPECT_LT(loose.max.iterations, tight.max.iterations / 2);
  EXPECT_NE(loose.max.message.find("relative change <= 0.001 in 3 iterations"), std::string::npos)
      << loose.max.message;
  EXPECT_TRUE(loose.max.stationary);
  EXPECT_LE(loose.max.amplitude, tight.max.amplitude);
  EXPECT_GT(loose.max.amplitude, 0.99 * tight.max.amplitude);
  EXPECT_GT(loose.max.amplitude, tight.min.amplitude);
}

// Next to an anti-resonance of blade 2's response (1127.55 Hz, a point of the case's 50-point
// curve) some α bring the response DOF to rest. From the seed −½ the projected gradient alone
// stops at a kink of the response within a few iterations, still at a sizeable fraction of the
// start's response; with the Gauss-Newton steps towards y = 0 (BoundsOptions::gauss_newton_minimum)
// the run ends decades lower, on a solution of R = 0 where its stopping test holds.
TEST(Cascade, GaussNewtonStepsBringTheResponseToRestWhereAlphaCan) {
  const auto b = CoarseBalanceAtH1();
  BoundsOptions o = EveryRunToItsEnd();
  o.alpha_seeds = {Eigen::VectorXd::Constant(b->num_alpha(), -0.5)};
  const double f = 1050.0 + 38.0 * 100.0 / 49.0;
  const BoundsResult gn = ComputeBounds(*b, f, o);
  o.gauss_newton_minimum = false;
  const BoundsResult pg = ComputeBounds(*b, f, o);
  ASSERT_TRUE(gn.min.IsUsable() && pg.min.IsUsable()) << gn.BriefReport() << pg.BriefReport();
  EXPECT_TRUE(gn.min.stationary);
  EXPECT_LE(gn.min.residual, 1e-6);
  EXPECT_LT(gn.min.amplitude, 1e-6 * gn.max.amplitude) << gn.min.message;
  EXPECT_GT(pg.min.amplitude, 1e3 * gn.min.amplitude) << pg.min.message;
  // The maximum runs take no Gauss-Newton steps: the same path either way.
  EXPECT_EQ(gn.max.amplitude, pg.max.amplitude);
}

// BoundsOptions::maximum_bfgs_memory: at 1086.73 Hz (H = 1, seed 0, no sample check) the
// projected-gradient maximum run zig-zags to the 200-iteration limit (no bound); the BFGS run
// stops, converged, after 51 iterations at y_max 6.12150e-5 m (2026-12-02). (Elsewhere the
// gradient finds the higher maximum: BoundsOptions.)
TEST(Cascade, MaximumRunsWithBfgsDirectionsConvergeWhereTheGradientCrawls) {
  const auto b = CoarseBalanceAtH1();
  BoundsOptions o;
  o.check_samples = 0;
  o.alpha_seeds = {Eigen::VectorXd::Zero(b->num_alpha())};
  ASSERT_EQ(o.maximum_bfgs_memory, 0);  // the default: the gradient
  const BoundsResult pg = ComputeBounds(*b, 1086.734693877551, o);
  o.maximum_bfgs_memory = 5;
  const BoundsResult bfgs = ComputeBounds(*b, 1086.734693877551, o);
  EXPECT_EQ(pg.max.status, BoundStatus::kMaxIterations) << pg.max.message;
  EXPECT_TRUE(std::isnan(pg.max.amplitude));  // a failed bound is never a number
  ASSERT_TRUE(bfgs.max.IsUsable()) << bfgs.max.message;
  EXPECT_LT(bfgs.max.iterations, 100);
  EXPECT_NEAR(bfgs.max.amplitude, 6.12150e-5, 1e-4 * 6.12150e-5);
  // The minimum runs keep the projected gradient: the same path either way.
  EXPECT_EQ(bfgs.min.amplitude, pg.min.amplitude);
}

}  // namespace
}  // namespace fricrom
