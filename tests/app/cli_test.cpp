// End-to-end tests of the fricrom command-line tool: runs the built executable (FRICROM_CLI) on
// the reference case and on bad input, checks JSON output, files and exit codes.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "app/cli_test_util.h"
#include "fricrom/blas_core.h"

namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using fricrom::testing::CliRun;
using fricrom::testing::Fricrom;
using fricrom::testing::kCli;
using fricrom::testing::Quote;
using fricrom::testing::ReadFile;
using fricrom::testing::Stderr;
using fricrom::testing::Stdout;
using fricrom::testing::TempDir;

using fricrom::testing::kBaseline;

TEST(Cli, ModesJsonMatchesTable3) {
  const CliRun r = Stdout("modes " + Quote(kBaseline) + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json j = json::parse(r.output);
  EXPECT_EQ(j.at("case"), "lumped3-baseline");
  const std::vector<double> free = j.at("free_hz").get<std::vector<double>>();
  const std::vector<double> stick = j.at("stick_hz").get<std::vector<double>>();
  // Zara et al. (2024), Table 3.
  const std::vector<double> free_ref = {87.17, 87.17, 159.15, 159.15, 246.56, 246.56};
  const std::vector<double> stick_ref = {84.58,  84.58,  168.19, 168.19, 266.89,
                                         266.89, 396.71, 396.71, 406.88, 406.88};
  ASSERT_EQ(free.size(), free_ref.size());
  ASSERT_EQ(stick.size(), stick_ref.size());
  for (size_t i = 0; i < free.size(); ++i)
    EXPECT_NEAR(free[i], free_ref[i], 0.01) << "free mode " << i + 1;
  for (size_t i = 0; i < stick.size(); ++i)
    EXPECT_NEAR(stick[i], stick_ref[i], 0.01) << "stick mode " << i + 1;
}

TEST(Cli, FrfAtFixedFrequenciesWritesJsonAndFiles) {
  TempDir tmp;
  const CliRun r =
      Stdout("frf " + Quote(kBaseline) + " --alpha 0,0,0,0 --freq 258,262,270 --json --out " +
             Quote(tmp.path().string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json j = json::parse(r.output);
  const json& pts = j.at("points");
  ASSERT_TRUE(pts.is_array());
  ASSERT_EQ(pts.size(), 3u);
  const std::vector<double> freqs = {258.0, 262.0, 270.0};
  const std::set<std::string> regimes = {"full-stick", "stick-slip", "full-slip",
                                         "stick-slip-liftoff", "lift-off"};
  for (size_t i = 0; i < 3; ++i) {
    const json& p = pts[i];
    EXPECT_DOUBLE_EQ(p.at("freq_hz").get<double>(), freqs[i]);
    const double amp = p.at("amplitude").get<double>();
    EXPECT_GT(amp, 1e-5) << "point " << i;
    EXPECT_LT(amp, 1e-3) << "point " << i;
    EXPECT_EQ(p.at("status"), "converged") << "point " << i;
    const json& states = p.at("states");
    ASSERT_TRUE(states.is_array());
    ASSERT_EQ(states.size(), 4u);
    for (const json& s : states) {
      ASSERT_TRUE(s.is_string());
      EXPECT_TRUE(regimes.count(s.get<std::string>())) << s;
    }
  }
  EXPECT_EQ(j.at("alpha").get<std::vector<double>>(), (std::vector<double>{0, 0, 0, 0}));
  EXPECT_EQ(j.at("contacts").get<std::vector<std::string>>(),
            (std::vector<std::string>{"c1", "c2", "c3", "c4"}));

  const fs::path h5 = tmp.path() / "frf.h5", csv = tmp.path() / "frf.csv";
  ASSERT_TRUE(fs::exists(h5));
  EXPECT_GT(fs::file_size(h5), 0u);
  ASSERT_TRUE(fs::exists(csv));
  std::istringstream lines(ReadFile(csv));
  std::vector<std::string> rows;
  for (std::string l; std::getline(lines, l);) {
    if (!l.empty()) rows.push_back(l);
  }
  ASSERT_EQ(rows.size(), 5u) << ReadFile(csv);  // 2 header lines + 3 points
  EXPECT_EQ(rows[0].rfind("#", 0), 0u) << rows[0];
  EXPECT_EQ(rows[1].rfind("freq_hz,amplitude_m,status", 0), 0u) << rows[1];
  EXPECT_EQ(rows[2].rfind("258,", 0), 0u) << rows[2];
  EXPECT_EQ(rows[3].rfind("262,", 0), 0u) << rows[3];
  EXPECT_EQ(rows[4].rfind("270,", 0), 0u) << rows[4];
  // The JSON names the files it wrote.
  EXPECT_EQ(fs::path(j.at("files").at("hdf5").get<std::string>()), h5);
  EXPECT_EQ(fs::path(j.at("files").at("csv").get<std::string>()), csv);
  // Written last, the manifest names the set: both files with their sizes.
  const json m = json::parse(ReadFile(tmp.path() / "frf.manifest.json"));
  ASSERT_EQ(m.at("files").size(), 2u);
  EXPECT_EQ(m.at("files")[0].at("file"), "frf.h5");
  EXPECT_EQ(m.at("files")[0].at("bytes").get<uintmax_t>(), fs::file_size(h5));
  EXPECT_EQ(m.at("files")[1].at("file"), "frf.csv");
  // ... and the build that wrote it (results of the two instruction sets differ at round-off).
  const std::string isa = m.at("build").at("instruction_set").get<std::string>();
  EXPECT_TRUE(isa == "x86-64-v3" || isa == "portable") << isa;
  // ... and the BLAS kernels it ran on (fricrom/blas_core.h).
  const std::string blas = m.at("build").at("blas").get<std::string>();
  EXPECT_TRUE(blas.rfind("OpenBLAS ", 0) == 0 || blas == "not OpenBLAS") << blas;
}

// `--version` names the BLAS kernels the run uses: where OpenBLAS fell back on its SSE3 kernels
// on an AVX2 CPU (this test process was not restarted, so it shows what OpenBLAS detects) the CLI
// restarted itself with the Haswell kernels and says so; a core the user set, or
// FRICROM_KEEP_BLAS_CORE=1, is kept as it is.
TEST(Cli, VersionNamesTheBlasCoreItRunsOn) {
  if (std::getenv("OPENBLAS_CORETYPE") != nullptr) GTEST_SKIP() << "OPENBLAS_CORETYPE is set";
  const std::string detected = fricrom::BlasCoreName();
  const std::string plain =
      detected.empty() ? "BLAS: not OpenBLAS)" : "BLAS: OpenBLAS " + detected + ")";
  const std::string forced = fricrom::RecommendedBlasCore();
  const CliRun r = Fricrom("--version", "2>&1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  if (forced.empty()) {
    EXPECT_NE(r.output.find(plain), std::string::npos) << r.output;
  } else {
    EXPECT_NE(
        r.output.find("BLAS: OpenBLAS " + forced + " (forced; OpenBLAS chose " + detected + "))"),
        std::string::npos)
        << r.output;
  }
  if (detected.empty()) return;
  const std::string cli = Quote(kCli);
  for (const std::string& env :
       {"OPENBLAS_CORETYPE=" + detected, std::string("FRICROM_KEEP_BLAS_CORE=1")}) {
    FILE* p = popen(("env " + env + " " + cli + " --version 2>&1").c_str(), "r");
    ASSERT_NE(p, nullptr);
    std::string out;
    std::array<char, 512> buf;
    for (size_t n; (n = fread(buf.data(), 1, buf.size(), p)) > 0;) out.append(buf.data(), n);
    EXPECT_EQ(pclose(p), 0) << env;
    EXPECT_NE(out.find(plain), std::string::npos) << env << ": " << out;
    EXPECT_EQ(out.find("forced"), std::string::npos) << env << ": " << out;
  }
}

// The baseline is mirror-symmetric (x -> -x maps blade1 <-> blade3, damper1 <-> damper2, contact
// c1 <-> c4, c2 <-> c3, and the excitation onto itself) and its solution is symmetric to round-off,
// so mirrored contacts must report the same state.
// Regression: at 270 Hz round-off used to decide stick vs slip where the periodic force touches
// the Coulomb limit exactly (fixed with a relative tolerance in the contact law).
TEST(Cli, FrfStatesRespectTheMirrorSymmetry) {
  TempDir tmp;
  const CliRun r =
      Stdout("frf " + Quote(kBaseline) + " --alpha 0,0,0,0 --freq 258,262,270 --json --out " +
             Quote(tmp.path().string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json j = json::parse(r.output);
  for (const json& p : j.at("points")) {
    const auto s = p.at("states").get<std::vector<std::string>>();
    ASSERT_EQ(s.size(), 4u);
    EXPECT_EQ(s[0], s[3]) << "c1 vs c4 at " << p.at("freq_hz") << " Hz";
    EXPECT_EQ(s[1], s[2]) << "c2 vs c3 at " << p.at("freq_hz") << " Hz";
  }
}

TEST(Cli, NonexistentCaseFile) {
  const std::string path = "/tmp/fricrom-no-such-dir/no-such-case.toml";
  const CliRun r = Stderr("modes " + Quote(path));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find(path), std::string::npos) << r.output;
}

TEST(Cli, AlphaWithWrongCount) {
  TempDir tmp;
  const CliRun r = Stderr("frf " + Quote(kBaseline) + " --alpha 0,0,0 --freq 262 --out " +
                          Quote(tmp.path().string()));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("fricrom: error:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--alpha"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("expected 4 values"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(tmp.path() / "frf.h5"));
}

TEST(Cli, AlphaOutOfRange) {
  TempDir tmp;
  const CliRun r = Stderr("frf " + Quote(kBaseline) + " --alpha 2,0,0,0 --freq 262 --out " +
                          Quote(tmp.path().string()));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("fricrom: error:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--alpha"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(tmp.path() / "frf.h5"));
}

TEST(Cli, UnknownParameterOverride) {
  const CliRun r = Stderr("modes " + Quote(kBaseline) + " --set nosuch=1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("fricrom: error:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("nosuch"), std::string::npos) << r.output;
}

TEST(Cli, LineSearchMemoryOutOfRangeIsAnError) {
  for (const char* bad : {"0", "101", "x"}) {
    const CliRun r =
        Stderr("bounds " + Quote(kBaseline) + " --freq 266 --line-search-memory " + bad);
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.output.find("--line-search-memory"), std::string::npos) << r.output;
  }
}

TEST(Cli, MaxBfgsMemoryOutOfRangeIsAnError) {
  for (const char* bad : {"-1", "101", "x"}) {
    const CliRun r = Stderr("bounds " + Quote(kBaseline) + " --freq 266 --max-bfgs-memory " + bad);
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.output.find("--max-bfgs-memory"), std::string::npos) << r.output;
  }
}

TEST(Cli, NegligibleMinimumOutsideZeroToOneIsAnError) {
  for (const char* bad : {"1", "-0.1", "nan", "x"}) {
    const CliRun r =
        Stderr("bounds " + Quote(kBaseline) + " --freq 266 --negligible-minimum " + bad);
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.output.find("--negligible-minimum"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("[0, 1)"), std::string::npos) << r.output;
  }
}

TEST(Cli, BadOverrideSyntax) {
  const CliRun r = Stderr("modes " + Quote(kBaseline) + " --set gamma=abc");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("gamma=abc"), std::string::npos) << r.output;
}

TEST(Cli, CaseFileWithUnknownKey) {
  TempDir tmp;
  std::string text = ReadFile(kBaseline);
  const auto pos = text.find("[response]");
  ASSERT_NE(pos, std::string::npos);
  text.insert(pos, "frobnicate = 1\n\n");
  const fs::path path = tmp.path() / "bad.toml";
  std::ofstream(path) << text;
  const CliRun r = Stderr("case " + Quote(path.string()));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("fricrom: error:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(path.string()), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("frobnicate"), std::string::npos) << r.output;
}

TEST(Cli, CasePrintsTheResolvedCase) {
  const CliRun r = Stdout("case " + Quote(kBaseline));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("lumped3-baseline"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("[[contacts]]"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("fricrom-case-1"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("10 DOFs, 4 contacts"), std::string::npos) << r.output;
  // Expressions are substituted: no parameter expression survives.
  EXPECT_EQ(r.output.find("theta_ref*("), std::string::npos) << r.output;
}

TEST(Cli, CaseAppliesOverrides) {
  const CliRun r = Stdout("case " + Quote(kBaseline) + " --set gamma=0.2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("120"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("180"), std::string::npos) << r.output;
}

// Issue 3's JSON contract for `bounds --freq` and `noa`.
TEST(Cli, BoundsJsonHasTheDocumentedKeys) {
  TempDir tmp;
  const CliRun r = Stdout("bounds " + Quote(kBaseline) + " --freq 266 --json --out " +
                          Quote(tmp.path().string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  for (const char* key : {"freq_hz", "y_min", "y_max", "eta_min", "eta_max", "alpha_at_min",
                          "alpha_at_max", "states_at_min", "states_at_max", "R", "status",
                          "mixed_configuration_at_min", "mixed_configuration_at_max"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j.at("status"), "converged");
  EXPECT_LE(j.at("y_min").get<double>(), j.at("y_max").get<double>());
  EXPECT_LE(j.at("eta_min").get<double>(), j.at("eta_max").get<double>());
  EXPECT_NEAR(j.at("R").get<double>(),
              1.0 - (j.at("y_max").get<double>() - j.at("y_min").get<double>()) /
                        j.at("y_max").get<double>(),
              1e-12);
  EXPECT_EQ(j.at("alpha_at_min").size(), 4u);
  EXPECT_EQ(j.at("states_at_min").size(), 4u);
  // Baseline near resonance: the mixed configuration on both dampers (paper Fig. 10).
  EXPECT_EQ(j.at("mixed_configuration_at_min"), nlohmann::json({true, true}));
  EXPECT_TRUE(fs::exists(tmp.path() / "bounds.h5"));
}

TEST(Cli, NoaJsonHasTheDocumentedKeys) {
  TempDir tmp;
  const CliRun r = Stdout("noa " + Quote(kBaseline) +
                          " --param beta --from 0 --to 0.2 --freq 266 --method reduced "
                          "--sweep-steps 5 --json --out " +
                          Quote(tmp.path().string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  for (const char* key : {"param", "p_opt", "R_opt", "eta1", "eta2", "outer_iterations",
                          "inner_solves", "wall_s", "manual_sweep"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j.at("param"), "beta");
  EXPECT_NEAR(j.at("R_opt").get<double>(), 1.0, 1e-6);
  EXPECT_EQ(j.at("manual_sweep").at("steps"), 5);
}

TEST(Cli, SweepOfAnUnknownParameterIsAnError) {
  const CliRun r =
      Stderr("sweep " + Quote(kBaseline) + " --param nosuch --from 0 --to 1 --steps 2");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("nosuch"), std::string::npos) << r.output;
}

// Issue 4: info and convert work on every real FE sample, and .mtx conversion keeps every digit.
TEST(Cli, InfoAndConvertWorkOnEveryFeSample) {
  const fs::path shared = fs::path(FRICROM_SOURCE_DIR) / ".." / "shared" / "fe-samples";
  std::vector<fs::path> files;
  if (fs::exists(shared)) {
    for (const auto& e : fs::recursive_directory_iterator(shared)) {
      const std::string ext = e.path().extension().string();
      if (ext == ".op4" || ext == ".pch" || ext == ".mtx") files.push_back(e.path());
    }
  }
  for (const auto& e :
       fs::recursive_directory_iterator(fs::path(FRICROM_SOURCE_DIR) / "tests" / "data")) {
    const std::string name = e.path().filename().string();
    if (name == "dmig.pch" || name == "inboard.op4" || name == "model_STIF1.mtx")
      files.push_back(e.path());
  }
  ASSERT_GE(files.size(), 3u);
  TempDir tmp;
  for (const fs::path& f : files) {
    const CliRun info = Stdout("info " + Quote(f.string()) + " --json");
    ASSERT_EQ(info.exit_code, 0) << f << "\n" << info.output;
    const auto j = nlohmann::json::parse(info.output);
    for (const auto& m : j.at("matrices")) {
      EXPECT_GE(m.at("rows").get<int64_t>(), 0) << f;
      if (m.at("type") != "real") continue;
      const fs::path out =
          tmp.path() / (f.stem().string() + "_" + m.at("name").get<std::string>() + ".mtx");
      const CliRun conv =
          Stdout("convert " + Quote(f.string()) + " --matrix " + m.at("name").get<std::string>() +
                 " --to " + Quote(out.string()) + " --json");
      ASSERT_EQ(conv.exit_code, 0) << f << " " << m.at("name") << "\n" << conv.output;
      const CliRun back = Stdout("info " + Quote(out.string()) + " --json");
      ASSERT_EQ(back.exit_code, 0) << out << "\n" << back.output;
      const auto jb = nlohmann::json::parse(back.output).at("matrices").at(0);
      EXPECT_EQ(jb.at("rows"), m.at("rows")) << out;
      EXPECT_EQ(jb.at("nnz"), m.at("nnz")) << out;
      // %.17g round-trips doubles exactly, so the norms agree to the last bit of the sum order.
      EXPECT_NEAR(jb.at("frobenius").get<double>(), m.at("frobenius").get<double>(),
                  1e-14 * m.at("frobenius").get<double>() + 1e-300)
          << out;
    }
    const CliRun h5 = Stdout("convert " + Quote(f.string()) + " --to " +
                             Quote((tmp.path() / (f.stem().string() + ".h5")).string()));
    EXPECT_EQ(h5.exit_code, 0) << f << "\n" << h5.output;
  }
}

TEST(Cli, InfoOnABadFileNamesIt) {
  TempDir tmp;
  const fs::path bad = tmp.path() / "broken.op4";
  std::ofstream(bad) << "this is not an OUTPUT4 file\n";
  const CliRun r = Stderr("info " + Quote(bad.string()));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("broken.op4"), std::string::npos) << r.output;
}

}  // namespace

namespace {

// `bounds --json` carries the Hill stability of both bounds: computed for the lumped case's full
// balance (the paper's bounds at 266 Hz are stable), noted as not computed for the condensed one.
TEST(Cli, BoundsJsonCarriesTheStabilityOfBothBounds) {
  TempDir tmp;
  const std::string out = " --out " + Quote(tmp.path().string());
  const CliRun lumped = Stdout("bounds " + Quote(kBaseline) + " --freq 266 --json" + out);
  ASSERT_EQ(lumped.exit_code, 0) << lumped.output;
  const json j = json::parse(lumped.output);
  for (const char* key : {"stability_min", "stability_max"}) {
    EXPECT_EQ(j.at(key).at("stable"), true) << key;
    EXPECT_LT(j.at(key).at("max_floquet_real_per_s").get<double>(), 0.0) << key;
  }
  const std::string as_fe = std::string(FRICROM_SOURCE_DIR) + "/meshes/lumped3/as_fe/case.toml";
  const CliRun fe = Stdout("bounds " + Quote(as_fe) + " --freq 266 --json" + out);
  ASSERT_EQ(fe.exit_code, 0) << fe.output;
  // The same system written as an FE assembly (condensed balance, modal Hill form with every
  // mode below its cutoff): the same verdict and leading exponent.
  const json k = json::parse(fe.output);
  for (const char* key : {"stability_min", "stability_max"}) {
    EXPECT_EQ(k.at(key).at("stable"), true) << key;
    EXPECT_NEAR(k.at(key).at("max_floquet_real_per_s").get<double>(),
                j.at(key).at("max_floquet_real_per_s").get<double>(),
                1e-4 * std::abs(j.at(key).at("max_floquet_real_per_s").get<double>()))
        << key;
  }
}

// bounds --stable-only: the lumped bounds at 266 Hz are stable, so they are their own stable
// bounds (exact), and no α sample (stable or not) lies outside them.
TEST(Cli, StableOnlyBoundsAreTheBoundsWhereTheBoundSolutionsAreStable) {
  TempDir tmp;
  const std::string out = " --out " + Quote(tmp.path().string());
  const CliRun plain = Stdout("bounds " + Quote(kBaseline) + " --freq 266 --json" + out);
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  EXPECT_FALSE(json::parse(plain.output).contains("stable_min"));
  const CliRun r = Stdout("bounds " + Quote(kBaseline) +
                          " --freq 266 --stable-only --stable-samples 12 --json" + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json j = json::parse(r.output);
  EXPECT_EQ(j.at("stable_candidates").at("judged").get<int>() +
                j.at("stable_candidates").at("failed").get<int>(),
            2 + 12);
  EXPECT_EQ(j.at("stable_candidates").at("beyond_bounds"), 0) << j.dump();
  EXPECT_EQ(j.at("stable_min").at("exact"), true);
  EXPECT_EQ(j.at("stable_max").at("exact"), true);
  EXPECT_DOUBLE_EQ(j.at("stable_min").at("amplitude_m").get<double>(), j.at("y_min").get<double>());
  EXPECT_DOUBLE_EQ(j.at("stable_max").at("amplitude_m").get<double>(), j.at("y_max").get<double>());
  EXPECT_NEAR(j.at("R_stable").get<double>(), j.at("R").get<double>(), 1e-15);
  EXPECT_LT(j.at("stable_max").at("max_floquet_real_per_s").get<double>(), 0.0);
  // A curve: the figure draws the stable bounds beside the bounds (scripts/plot_bounds.py).
  const CliRun curve = Stdout("bounds " + Quote(kBaseline) +
                              " --range 262 270 --points 3 --stable-only --stable-samples 4 "
                              "--plot --quiet" +
                              out);
  ASSERT_EQ(curve.exit_code, 0) << curve.output;
  EXPECT_TRUE(fs::exists(tmp.path() / "bounds.png"));
}

// frf --stability --time-check: Hill and the time integration from each solution judge every
// point (the lumped benchmark's are stable, and the runs stay on them); the HDF5 file keeps the
// verdicts.
TEST(Cli, FrfJudgesEachPointByHillAndByTimeIntegration) {
  TempDir tmp;
  const CliRun r = Stdout("frf " + Quote(kBaseline) +
                          " --freq 262,266,270 --stability --time-check --json --out " +
                          Quote(tmp.path().string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json j = json::parse(r.output);
  ASSERT_EQ(j.at("points").size(), 3u);
  for (const json& p : j.at("points")) {
    EXPECT_EQ(p.at("stability").at("computed"), true) << p.dump();
    EXPECT_EQ(p.at("stability").at("stable"), true) << p.dump();
    EXPECT_EQ(p.at("time_check").at("holds"), true) << p.dump();
  }
  std::ifstream csv(tmp.path() / "frf.csv");
  std::string header, line;
  std::getline(csv, header);  // the comment line
  std::getline(csv, header);
  EXPECT_NE(header.find(",stable,time_holds"), std::string::npos) << header;
  std::getline(csv, line);
  EXPECT_EQ(line.substr(line.size() - 4), ",1,1") << line;
}

// verify judges both bound solutions by Hill and by time integration, and the two agree.
TEST(Cli, VerifyJudgesBothBoundSolutionsTwice) {
  TempDir tmp;
  const CliRun r = Stdout("verify " + Quote(kBaseline) +
                          " --freq 266 --alpha-samples 8 --time-runs 1 --json --out " +
                          Quote(tmp.path().string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json j = json::parse(r.output);
  for (const char* name : {"min", "max"}) {
    const json& b = j.at("bound_stability").at(name);
    EXPECT_EQ(b.at("hill").at("stable"), true) << b.dump();
    EXPECT_EQ(b.at("time_integration").at("holds"), true) << b.dump();
    EXPECT_EQ(b.at("agree"), true) << b.dump();
  }
}

}  // namespace
