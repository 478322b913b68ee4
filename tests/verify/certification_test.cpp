// The certification verdict (issue 9, defect 2): no evidence, or any failure, is no certificate.
#include "fricrom/certification.h"

#include <gtest/gtest.h>

#include <string>

namespace fricrom {
namespace {

TEST(Certification, NothingCheckedIsNotCertified) {
  // verify --set mu=0 --alpha-samples 20 --time-runs 0 used to say "certified" with 0 converged.
  const auto gaps = CertificationGaps({20, 20, 0, 0, 0, 0});
  ASSERT_FALSE(gaps.empty());
  EXPECT_EQ(gaps[0], "nothing was checked");
  EXPECT_EQ(gaps[1], "20 of 20 alpha samples did not converge");
  EXPECT_FALSE(CertificationGaps({0, 0, 0, 0, 0, 0}).empty());
}

TEST(Certification, AnyFailureOrOutlierBreaksTheCertificate) {
  EXPECT_TRUE(CertificationGaps({20, 0, 0, 4, 0, 0}).empty());
  EXPECT_TRUE(CertificationGaps({0, 0, 0, 2, 0, 0}).empty());  // time integration alone is evidence
  EXPECT_EQ(CertificationGaps({20, 1, 0, 4, 0, 0}).size(), 1u);
  EXPECT_EQ(CertificationGaps({20, 0, 2, 4, 0, 0}).size(), 1u);
  EXPECT_EQ(CertificationGaps({20, 0, 0, 4, 1, 0}).size(), 1u);
  EXPECT_EQ(CertificationGaps({20, 0, 0, 4, 0, 1}).size(), 1u);
  EXPECT_EQ(CertificationGaps({0, 0, 0, 2, 2, 0}).size(), 2u);  // no steady state: nothing checked
}

// A time integration that ends at a harmonic-balance solution beyond the bounds proves them local,
// even when the run itself was not steady (and so never counted as "outside").
TEST(Certification, AnHbmSolutionBeyondTheBoundsBreaksTheCertificate) {
  const auto gaps = CertificationGaps({200, 0, 0, 4, 1, 0, 1});
  ASSERT_EQ(gaps.size(), 2u);
  EXPECT_NE(gaps[1].find("beyond the bounds"), std::string::npos) << gaps[1];
  EXPECT_TRUE(CertificationGaps({200, 0, 0, 4, 0, 0, 0}).empty());
}

// A bound run that a check beat is reported as beaten and never certified, even where everything
// lies inside the bounds improved from the check's solution.
TEST(Certification, ABeatenBoundRunIsNeverCertified) {
  CertificationEvidence e{200, 0, 0, 4, 0, 0, 0};
  e.bounds_beaten = 1;
  const auto gaps = CertificationGaps(e);
  ASSERT_EQ(gaps.size(), 1u);
  EXPECT_NE(gaps[0].find("beaten"), std::string::npos) << gaps[0];
}

}  // namespace
}  // namespace fricrom
