// A reduced-space run's start on the lumped benchmark, shared by the bound-run tests: a
// harmonic-balance solution at 269 Hz and a generic α, and the run set-up for it.
#pragma once

#include <Eigen/Dense>

#include "bounds/bound_runs.h"
#include "fricrom/frf.h"
#include "fricrom/units.h"
#include "test_models.h"

namespace fricrom::bounds_detail::testing_runs {

struct LumpedRunStart {
  Eigen::Vector4d a0{-0.7, 0.2, 0.6, -0.1};
  FrfPoint start;  // check start.status before using it
  RunSetup setup;  // sign and stall test left to the test
};

inline LumpedRunStart LumpedRunAt269Hz() {
  LumpedRunStart r;
  const HbmSystem& sys = testing::BaselineH1();
  const double f = 269.0;
  r.start = SolveAtFrequency(sys, r.a0, f, Eigen::VectorXd(), FrfOptions());
  r.setup.system = &sys;
  r.setup.omega = RadPerS(f);
  r.setup.residual_scale = sys.ResidualScale();
  r.setup.objective_scale = r.start.amplitude * r.start.amplitude;
  r.setup.line_search_memory = 10;
  r.setup.gauss_newton = true;
  return r;
}

}  // namespace fricrom::bounds_detail::testing_runs
