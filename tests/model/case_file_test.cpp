// Tests of the TOML case parser (src/model/case_file.cpp): the reference case, parameter
// overrides and the error messages for bad input. Cases under test are built from the text of
// meshes/lumped3/baseline.toml by string replacement.
#include "fricrom/case_file.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace fricrom {
namespace {

const std::string kBaselinePath = std::string(FRICROM_SOURCE_DIR) + "/meshes/lumped3/baseline.toml";

std::string BaselineText() {
  std::ifstream in(kBaselinePath);
  EXPECT_TRUE(in.good()) << "cannot read " << kBaselinePath;
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Replaces the first occurrence of `from` (which must occur) by `to`.
std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << "'" << from << "' not found in the case text";
  if (pos == std::string::npos) return text;
  text.replace(pos, from.size(), to);
  return text;
}

// 1-based line of the first occurrence of `fragment` (which must occur).
int LineOf(const std::string& text, const std::string& fragment) {
  const auto pos = text.find(fragment);
  EXPECT_NE(pos, std::string::npos) << "'" << fragment << "' not found";
  if (pos == std::string::npos) return -1;
  int line = 1;
  for (size_t i = 0; i < pos; ++i) line += text[i] == '\n';
  return line;
}

// Parses `text` expecting a CaseError; returns its message ("" and a failure if none is thrown).
std::string ErrorOf(const std::string& text, const std::vector<ParameterOverride>& overrides = {}) {
  try {
    ParseCase(text, "test.toml", overrides);
  } catch (const CaseError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected CaseError, got another exception: " << e.what();
    return e.what();
  }
  ADD_FAILURE() << "expected CaseError, nothing thrown";
  return "";
}

// Index of `name` in the case DOFs (asserting it exists).
int Dof(const Case& c, const std::string& name) {
  const int i = c.model.DofIndex(name);
  EXPECT_GE(i, 0) << name;
  return i;
}

const HarmonicLoad* LoadAt(const Case& c, int harmonic) {
  for (const HarmonicLoad& l : c.model.loads) {
    if (l.harmonic == harmonic) return &l;
  }
  return nullptr;
}

constexpr double kPi4 = std::numbers::pi / 4;

// ------------------------------------------------------------------------- the reference case

TEST(CaseFile, BaselineLoads) {
  const Case c = LoadCase(kBaselinePath);
  const Model& m = c.model;
  EXPECT_EQ(c.name, "lumped3-baseline");
  EXPECT_EQ(c.source, kBaselinePath);
  ASSERT_EQ(m.num_dofs(), 10);
  const std::vector<std::string> names = {"blade1.x",  "blade1.y", "blade2.x",  "blade2.y",
                                          "blade3.x",  "blade3.y", "damper1.x", "damper1.y",
                                          "damper2.x", "damper2.y"};
  EXPECT_EQ(m.dof_names, names);

  ASSERT_EQ(m.contacts.size(), 4u);
  EXPECT_EQ(c.contact_names, (std::vector<std::string>{"c1", "c2", "c3", "c4"}));
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(m.contacts[i].name, "c" + std::to_string(i + 1));
    EXPECT_DOUBLE_EQ(m.contacts[i].kn, 3e5);
    EXPECT_DOUBLE_EQ(m.contacts[i].kt, 3e5);
    EXPECT_DOUBLE_EQ(m.contacts[i].mu, 0.5);
    EXPECT_DOUBLE_EQ(m.contacts[i].normal_preload, 0.0);
  }
  // c1: damper1 (A) against blade1 (B).
  EXPECT_EQ(m.contacts[0].dofs_a, (std::vector<int>{Dof(c, "damper1.x"), Dof(c, "damper1.y")}));
  EXPECT_EQ(m.contacts[0].dofs_b, (std::vector<int>{Dof(c, "blade1.x"), Dof(c, "blade1.y")}));
  EXPECT_EQ(m.contacts[3].dofs_a, (std::vector<int>{Dof(c, "damper2.x"), Dof(c, "damper2.y")}));
  EXPECT_EQ(m.contacts[3].dofs_b, (std::vector<int>{Dof(c, "blade3.x"), Dof(c, "blade3.y")}));

  EXPECT_EQ(m.dof_names[m.response_dof], "blade2.y");
  EXPECT_EQ(c.analysis.harmonics, 1);
  EXPECT_EQ(c.analysis.samples_per_period, 128);
  EXPECT_DOUBLE_EQ(c.analysis.freq_min_hz, 240.0);
  EXPECT_DOUBLE_EQ(c.analysis.freq_max_hz, 290.0);
  EXPECT_EQ(c.analysis.alpha, (std::vector<double>{0.0, 0.0, 0.0, 0.0}));

  // Loads: static preload (h = 0) on the dampers, excitation (h = 1) on blades 1 and 3.
  ASSERT_EQ(m.loads.size(), 2u);
  const HarmonicLoad* l0 = LoadAt(c, 0);
  const HarmonicLoad* l1 = LoadAt(c, 1);
  ASSERT_NE(l0, nullptr);
  ASSERT_NE(l1, nullptr);
  Eigen::VectorXd pre = Eigen::VectorXd::Zero(10), exc = Eigen::VectorXd::Zero(10);
  pre[Dof(c, "damper1.y")] = 150.0;
  pre[Dof(c, "damper2.y")] = 150.0;
  exc[Dof(c, "blade1.x")] = 5.0;
  exc[Dof(c, "blade1.y")] = 20.0;
  exc[Dof(c, "blade3.x")] = -5.0;
  exc[Dof(c, "blade3.y")] = 20.0;
  EXPECT_TRUE(l0->cos.isApprox(pre, 1e-14)) << l0->cos.transpose();
  EXPECT_EQ(l0->sin.norm(), 0.0);
  EXPECT_TRUE(l1->cos.isApprox(exc, 1e-14)) << l1->cos.transpose();
  EXPECT_EQ(l1->sin.norm(), 0.0);

  // Free system = the 6 blade DOFs.
  std::vector<int> blades;
  for (const char* n : {"blade1.x", "blade1.y", "blade2.x", "blade2.y", "blade3.x", "blade3.y"}) {
    blades.push_back(Dof(c, n));
  }
  EXPECT_EQ(m.free_dofs, blades);

  // Matrices: symmetric, with the values of Table 2.
  EXPECT_EQ((m.mass - m.mass.transpose()).norm(), 0.0);
  EXPECT_EQ((m.stiffness - m.stiffness.transpose()).norm(), 0.0);
  EXPECT_EQ((m.damping - m.damping.transpose()).norm(), 0.0);
  EXPECT_DOUBLE_EQ(m.mass(Dof(c, "blade1.x"), Dof(c, "blade1.x")), 1.0);
  EXPECT_DOUBLE_EQ(m.mass(Dof(c, "damper1.y"), Dof(c, "damper1.y")), 0.1);
  EXPECT_DOUBLE_EQ(m.stiffness(Dof(c, "blade1.x"), Dof(c, "blade1.x")), 3e5 + 7e5);
  EXPECT_DOUBLE_EQ(m.stiffness(Dof(c, "blade2.y"), Dof(c, "blade2.y")), 3e5 + 2 * 7e5);
  EXPECT_DOUBLE_EQ(m.stiffness(Dof(c, "blade1.y"), Dof(c, "blade2.y")), -7e5);
  EXPECT_DOUBLE_EQ(m.stiffness(Dof(c, "blade1.x"), Dof(c, "blade2.y")), 0.0);
  EXPECT_DOUBLE_EQ(m.stiffness(Dof(c, "damper2.x"), Dof(c, "damper2.x")), 3e3);
  EXPECT_DOUBLE_EQ(m.damping(Dof(c, "blade3.y"), Dof(c, "blade3.y")), 20.0);
  EXPECT_DOUBLE_EQ(m.damping(Dof(c, "damper1.x"), Dof(c, "damper1.x")), 0.0);
}

TEST(CaseFile, ContactGeometryAtFortyFiveDegrees) {
  const Case c = LoadCase(kBaselinePath);
  const double h = std::sqrt(2.0) / 2;
  const auto& c1 = c.model.contacts[0];
  const auto& c2 = c.model.contacts[1];
  ASSERT_EQ(c1.normal.size(), 2);
  ASSERT_EQ(c1.tangent.size(), 2);
  EXPECT_NEAR(c1.normal[0], -h, 1e-12);
  EXPECT_NEAR(c1.normal[1], h, 1e-12);
  EXPECT_NEAR(c1.tangent[0], h, 1e-12);
  EXPECT_NEAR(c1.tangent[1], h, 1e-12);
  EXPECT_NEAR(c2.normal[0], h, 1e-12);
  EXPECT_NEAR(c2.normal[1], h, 1e-12);
  EXPECT_NEAR(c2.tangent[0], h, 1e-12);
  EXPECT_NEAR(c2.tangent[1], -h, 1e-12);
  for (const Contact& k : c.model.contacts) {
    EXPECT_NEAR(k.normal.dot(k.tangent), 0.0, 1e-14) << k.name;
    EXPECT_NEAR(k.normal.norm(), 1.0, 1e-14) << k.name;
    EXPECT_NEAR(k.tangent.norm(), 1.0, 1e-14) << k.name;
  }
  // c3 faces left like c1, c4 right like c2 (all at pi/4 when beta = 0).
  EXPECT_TRUE(c.model.contacts[2].normal.isApprox(c1.normal, 1e-14));
  EXPECT_TRUE(c.model.contacts[3].normal.isApprox(c2.normal, 1e-14));
}

// ------------------------------------------------------------------------- overrides

TEST(CaseFile, GammaOverrideSplitsThePreload) {
  const Case c = ParseCase(BaselineText(), "test.toml", {ParseOverride("gamma=0.2")});
  EXPECT_DOUBLE_EQ(c.parameters.at("gamma"), 0.2);
  const HarmonicLoad* l0 = LoadAt(c, 0);
  ASSERT_NE(l0, nullptr);
  EXPECT_NEAR(l0->cos[Dof(c, "damper1.y")], 120.0, 1e-12);  // F0 (1 - gamma), Eq. 11
  EXPECT_NEAR(l0->cos[Dof(c, "damper2.y")], 180.0, 1e-12);  // F0 (1 + gamma)
}

TEST(CaseFile, BetaOverrideChangesTheWedgeAngles) {
  const Case c = ParseCase(BaselineText(), "test.toml", {ParameterOverride{"beta", 0.1}});
  const double t_out = 0.9 * kPi4, t_in = 1.1 * kPi4;  // Eq. 12
  const auto& k = c.model.contacts;
  ASSERT_EQ(k.size(), 4u);
  // Left faces (c1, c3): normal = (-sin θ, cos θ); right faces (c2, c4): (sin θ, cos θ).
  EXPECT_NEAR(k[0].normal[0], -std::sin(t_out), 1e-12);
  EXPECT_NEAR(k[0].normal[1], std::cos(t_out), 1e-12);
  EXPECT_NEAR(k[1].normal[0], std::sin(t_in), 1e-12);
  EXPECT_NEAR(k[1].normal[1], std::cos(t_in), 1e-12);
  EXPECT_NEAR(k[2].normal[0], -std::sin(t_in), 1e-12);
  EXPECT_NEAR(k[2].normal[1], std::cos(t_in), 1e-12);
  EXPECT_NEAR(k[3].normal[0], std::sin(t_out), 1e-12);
  EXPECT_NEAR(k[3].normal[1], std::cos(t_out), 1e-12);
  for (const Contact& ct : k) EXPECT_NEAR(ct.normal.dot(ct.tangent), 0.0, 1e-14) << ct.name;
}

TEST(CaseFile, ParseOverride) {
  const ParameterOverride o = ParseOverride("gamma=0.2");
  EXPECT_EQ(o.name, "gamma");
  EXPECT_DOUBLE_EQ(o.value, 0.2);
  EXPECT_DOUBLE_EQ(ParseOverride("kn=3e5").value, 3e5);
  EXPECT_THROW(ParseOverride("gamma"), CaseError);
  EXPECT_THROW(ParseOverride("=1"), CaseError);
  EXPECT_THROW(ParseOverride("gamma="), CaseError);
  EXPECT_THROW(ParseOverride("gamma=abc"), CaseError);
  EXPECT_THROW(ParseOverride("gamma=0.2x"), CaseError);
  EXPECT_THROW(ParseOverride("gamma=inf"), CaseError);
  try {
    ParseOverride("gamma=abc");
  } catch (const CaseError& e) {
    EXPECT_NE(std::string(e.what()).find("gamma=abc"), std::string::npos) << e.what();
  }
}

TEST(CaseFile, UnknownOverrideIsAnError) {
  const std::string msg = ErrorOf(BaselineText(), {ParameterOverride{"nosuch", 1.0}});
  EXPECT_NE(msg.find("nosuch"), std::string::npos) << msg;
  EXPECT_NE(msg.find("test.toml"), std::string::npos) << msg;
  EXPECT_NE(msg.find("gamma"), std::string::npos) << msg;  // lists the defined parameters
}

// ------------------------------------------------------------------------- errors

// Expects every fragment in `msg`.
void ExpectContains(const std::string& msg, const std::vector<std::string>& fragments) {
  for (const std::string& f : fragments) {
    EXPECT_NE(msg.find(f), std::string::npos) << "'" << f << "' missing from: " << msg;
  }
}

TEST(CaseFileErrors, UnknownTopLevelKey) {
  const std::string text =
      Replace(BaselineText(), "units = \"SI\"\n", "units = \"SI\"\nfrobnicate = 1\n");
  const std::string line = ":" + std::to_string(LineOf(text, "frobnicate = 1")) + ":";
  ExpectContains(ErrorOf(text), {"test.toml" + line, "frobnicate", "unknown key", "schema"});
}

TEST(CaseFileErrors, UnknownKeyInAContact) {
  const std::string text =
      Replace(BaselineText(), "damper = \"damper1\"\ncounterpart = \"blade1\"",
              "frobnicate = 1\ndamper = \"damper1\"\ncounterpart = \"blade1\"");
  const std::string line = ":" + std::to_string(LineOf(text, "frobnicate = 1")) + ":";
  ExpectContains(ErrorOf(text),
                 {"test.toml" + line, "contacts[0].frobnicate", "unknown key", "theta"});
}

TEST(CaseFileErrors, MissingRequiredKey) {
  const std::string text = Replace(BaselineText(), "mu = \"mu\"\n", "");
  ExpectContains(ErrorOf(text), {"test.toml", "contacts[0].mu", "missing"});
}

TEST(CaseFileErrors, NonPositiveMass) {
  const std::string text = Replace(BaselineText(), "mass = \"m\"", "mass = -1");
  const std::string line = ":" + std::to_string(LineOf(text, "mass = -1")) + ":";
  ExpectContains(ErrorOf(text), {"test.toml" + line, "bodies[0].mass", "> 0", "-1"});
}

TEST(CaseFileErrors, BadExpression) {
  const std::string text =
      Replace(BaselineText(), "theta = \"theta_ref*(1-beta)\"", "theta = \"theta_ref*(1-\"");
  const std::string line = ":" + std::to_string(LineOf(text, "theta = \"theta_ref*(1-\"")) + ":";
  ExpectContains(ErrorOf(text), {"test.toml" + line, "contacts[0].theta", "theta_ref*(1-"});
}

TEST(CaseFileErrors, UnknownParameterInExpression) {
  const std::string text = Replace(BaselineText(), "kt = \"kt\"", "kt = \"kt_nosuch\"");
  ExpectContains(ErrorOf(text), {"test.toml", "contacts[0].kt", "kt_nosuch"});
}

TEST(CaseFileErrors, ThetaOutOfRange) {
  const std::string text =
      Replace(BaselineText(), "theta = \"theta_ref*(1+beta)\"", "theta = \"2*theta_ref*(1+beta)\"");
  ExpectContains(ErrorOf(text), {"test.toml", "contacts[1].theta", "pi/2"});
}

TEST(CaseFileErrors, UnknownBodyInASpring) {
  const std::string text = Replace(BaselineText(), "between = [\"blade1\", \"blade2\"]",
                                   "between = [\"blade1\", \"bladeX\"]");
  const std::string line = ":" + std::to_string(LineOf(text, "bladeX")) + ":";
  ExpectContains(ErrorOf(text), {"test.toml" + line, "springs[0].between", "bladeX"});
}

TEST(CaseFileErrors, UnknownCounterpart) {
  const std::string text =
      Replace(BaselineText(), "counterpart = \"blade3\"", "counterpart = \"blade7\"");
  ExpectContains(ErrorOf(text), {"test.toml", "contacts[3].counterpart", "blade7"});
}

TEST(CaseFileErrors, AlphaWithThreeValues) {
  const std::string text =
      Replace(BaselineText(), "alpha = [0.0, 0.0, 0.0, 0.0]", "alpha = [0.0, 0.0, 0.0]");
  const std::string line = ":" + std::to_string(LineOf(text, "alpha = [")) + ":";
  ExpectContains(ErrorOf(text),
                 {"test.toml" + line, "analysis.alpha", "one value per contact", "4"});
}

TEST(CaseFileErrors, AlphaOutOfRange) {
  const std::string text =
      Replace(BaselineText(), "alpha = [0.0, 0.0, 0.0, 0.0]", "alpha = [0.0, 1.5, 0.0, 0.0]");
  ExpectContains(ErrorOf(text), {"test.toml", "analysis.alpha[1]", "[-1, 1]"});
}

TEST(CaseFileErrors, SearchHarmonicsOtherThanZeroOrOne) {
  for (const char* bad : {"2", "0.5", "-1", "\"ladder\""}) {
    const std::string text =
        Replace(BaselineText(), "alpha = [0.0, 0.0, 0.0, 0.0]",
                std::string("alpha = [0.0, 0.0, 0.0, 0.0]\nsearch_harmonics = ") + bad);
    ExpectContains(ErrorOf(text), {"test.toml", "analysis.search_harmonics"});
  }
  const std::string ok = Replace(BaselineText(), "alpha = [0.0, 0.0, 0.0, 0.0]",
                                 "alpha = [0.0, 0.0, 0.0, 0.0]\nsearch_harmonics = 1");
  EXPECT_EQ(ParseCase(ok, "test.toml", {}).analysis.search_harmonics, 1);
  EXPECT_EQ(ParseCase(BaselineText(), "test.toml", {}).analysis.search_harmonics, 0);
}

TEST(CaseFileErrors, WrongSchema) {
  const std::string text =
      Replace(BaselineText(), "schema = \"fricrom-case-1\"", "schema = \"fricrom-case-9\"");
  const std::string line = ":" + std::to_string(LineOf(text, "schema = ")) + ":";
  ExpectContains(ErrorOf(text), {"test.toml" + line, "schema", "fricrom-case-1", "fricrom-case-9"});
}

TEST(CaseFileErrors, TomlSyntaxError) {
  const std::string text = Replace(BaselineText(), "kind = \"damper\"", "kind = \"damper");
  const std::string line = ":" + std::to_string(LineOf(text, "kind = \"damper")) + ":";
  ExpectContains(ErrorOf(text), {"test.toml" + line, "TOML syntax error"});
}

TEST(CaseFileErrors, BadFace) {
  const std::string text = Replace(BaselineText(), "face = \"left\"", "face = \"up\"");
  const std::string line = ":" + std::to_string(LineOf(text, "face = \"up\"")) + ":";
  ExpectContains(ErrorOf(text), {"test.toml" + line, "contacts[0].face", "left", "right", "up"});
}

TEST(CaseFileErrors, UnknownResponseDof) {
  const std::string text = Replace(BaselineText(), "dof = \"blade2.y\"", "dof = \"blade9.y\"");
  const std::string line = ":" + std::to_string(LineOf(text, "dof = \"blade9.y\"")) + ":";
  ExpectContains(ErrorOf(text), {"test.toml" + line, "response.dof", "blade9.y"});
}

TEST(CaseFileErrors, UnknownLoadDof) {
  const std::string text = Replace(BaselineText(), "dof = \"blade1.x\"", "dof = \"blade1.z\"");
  ExpectContains(ErrorOf(text), {"test.toml", "loads[2].dof", "blade1.z"});
}

TEST(CaseFileErrors, NonexistentFile) {
  const std::string path = "/tmp/fricrom-no-such-dir/no-such-case.toml";
  try {
    LoadCase(path);
    FAIL() << "expected CaseError";
  } catch (const CaseError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

// ------------------------------------------------------------------------- resolved case

TEST(CaseFile, ResolvedCaseParsesAgainToTheSameModel) {
  const Case a = ParseCase(BaselineText(), "test.toml",
                           {ParameterOverride{"beta", 0.1}, ParameterOverride{"gamma", 0.2}});
  ASSERT_FALSE(a.resolved.empty());
  Case b;
  try {
    b = ParseCase(a.resolved, "resolved.toml");
  } catch (const CaseError& e) {
    FAIL() << "the resolved case does not parse again: " << e.what() << "\n" << a.resolved;
  }
  EXPECT_EQ(b.name, a.name);
  EXPECT_EQ(b.model.dof_names, a.model.dof_names);
  EXPECT_EQ(b.contact_names, a.contact_names);
  EXPECT_EQ(b.parameters, a.parameters);
  EXPECT_TRUE(b.model.stiffness.isApprox(a.model.stiffness, 1e-15));
  EXPECT_TRUE(b.model.mass.isApprox(a.model.mass, 1e-15));
  EXPECT_TRUE(b.model.damping.isApprox(a.model.damping, 1e-15));
  EXPECT_EQ(b.model.response_dof, a.model.response_dof);
  EXPECT_EQ(b.model.free_dofs, a.model.free_dofs);
  ASSERT_EQ(b.model.contacts.size(), a.model.contacts.size());
  for (size_t i = 0; i < a.model.contacts.size(); ++i) {
    EXPECT_TRUE(b.model.contacts[i].normal.isApprox(a.model.contacts[i].normal, 1e-15));
    EXPECT_TRUE(b.model.contacts[i].tangent.isApprox(a.model.contacts[i].tangent, 1e-15));
    EXPECT_DOUBLE_EQ(b.model.contacts[i].mu, a.model.contacts[i].mu);
  }
  ASSERT_EQ(b.model.loads.size(), a.model.loads.size());
  for (size_t i = 0; i < a.model.loads.size(); ++i) {
    EXPECT_EQ(b.model.loads[i].harmonic, a.model.loads[i].harmonic);
    EXPECT_TRUE(b.model.loads[i].cos.isApprox(a.model.loads[i].cos, 1e-15));
  }
  EXPECT_EQ(b.analysis.harmonics, a.analysis.harmonics);
  EXPECT_EQ(b.analysis.samples_per_period, a.analysis.samples_per_period);
  EXPECT_EQ(b.analysis.alpha, a.analysis.alpha);
  // Resolving is idempotent.
  EXPECT_EQ(b.resolved, a.resolved);
}

}  // namespace
}  // namespace fricrom
