#include "fricrom/cyclic.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace fricrom {

namespace {

void RequireCyclic(const Model& sector, const char* who) {
  if (sector.cyclic.sectors == 0) {
    throw std::invalid_argument(std::string(who) + ": the model has no cyclic symmetry");
  }
  sector.cyclic.Validate();
}

// Sector s's loads: the sector's, delayed by s·φ harmonic by harmonic.
HarmonicLoad DelayedLoad(const HarmonicLoad& load, double delay, int n, int offset, int total) {
  HarmonicLoad out;
  out.harmonic = load.harmonic;
  out.cos = Eigen::VectorXd::Zero(total);
  out.sin = Eigen::VectorXd::Zero(total);
  for (int d = 0; d < n; ++d) {
    double a = load.cos[d], b = load.sin[d];
    if (load.harmonic > 0) RotateHarmonic(load.harmonic * delay, &a, &b);
    out.cos[offset + d] = a;
    out.sin[offset + d] = b;
  }
  return out;
}

}  // namespace

int NodalDiameterOfHarmonic(const CyclicSymmetry& cyclic, int harmonic) {
  cyclic.Validate();
  const int k = (harmonic * cyclic.engine_order) % cyclic.sectors;
  return std::min(k, cyclic.sectors - k);
}

Model ExpandCyclicRing(const Model& sector, bool alpha_per_sector) {
  RequireCyclic(sector, "ExpandCyclicRing");
  sector.Validate();
  const int ns = sector.cyclic.sectors, n = sector.num_dofs(), total = ns * n;
  const int groups = sector.num_alpha();
  Model ring;
  ring.mass = Eigen::MatrixXd::Zero(total, total);
  ring.damping = Eigen::MatrixXd::Zero(total, total);
  ring.stiffness = Eigen::MatrixXd::Zero(total, total);
  for (int s = 0; s < ns; ++s) {
    const int o = s * n;
    ring.mass.block(o, o, n, n) = sector.mass;
    ring.damping.block(o, o, n, n) = sector.damping;
    ring.stiffness.block(o, o, n, n) = sector.stiffness;
    std::string prefix = "s";
    prefix += std::to_string(s);
    prefix += '.';
    for (const std::string& name : sector.dof_names) ring.dof_names.push_back(prefix + name);
    for (const int d : sector.free_dofs) ring.free_dofs.push_back(o + d);
    for (size_t c = 0; c < sector.contacts.size(); ++c) {
      const Contact& ct = sector.contacts[c];
      Contact copy = ct;
      copy.name = prefix + ct.name;
      const int ob = ct.cyclic() ? ((s + 1) % ns) * n : o;
      for (int& d : copy.dofs_a) d = d >= 0 ? d + o : d;
      for (int& d : copy.dofs_b) d = d >= 0 ? d + ob : d;
      copy.phase_b = 0.0;  // the ring holds the next sector's DOFs themselves
      ring.contacts.push_back(copy);
      const int g = sector.alpha_group.empty() ? static_cast<int>(c) : sector.alpha_group[c];
      ring.alpha_group.push_back(alpha_per_sector ? g + s * groups : g);
    }
    for (const HarmonicLoad& load : sector.loads) {
      ring.loads.push_back(DelayedLoad(load, s * sector.cyclic.phase(), n, o, total));
    }
  }
  ring.response_dof = sector.response_dof;
  ring.Validate();
  return ring;
}

Eigen::VectorXd RingContactAlpha(const Model& sector, const std::vector<ContactHistory>& histories,
                                 const Eigen::VectorXd& contact_alpha) {
  RequireCyclic(sector, "RingContactAlpha");
  const int nc = static_cast<int>(sector.contacts.size()), ns = sector.cyclic.sectors;
  if (static_cast<int>(histories.size()) != nc || contact_alpha.size() != nc) {
    throw std::invalid_argument("RingContactAlpha: needs one history and one α per contact (" +
                                std::to_string(nc) + ")");
  }
  const int samples = nc > 0 ? static_cast<int>(histories[0].tangential.size()) : 0;
  const long shift = static_cast<long>(samples) * sector.cyclic.engine_order;
  if (nc > 0 && shift % ns != 0) {
    throw std::invalid_argument("RingContactAlpha: samples per period (" + std::to_string(samples) +
                                ") times the engine "
                                "order must be a multiple of the sectors (" +
                                std::to_string(ns) + ")");
  }
  Eigen::VectorXd out(static_cast<Eigen::Index>(ns) * nc);
  for (int s = 0; s < ns; ++s) {
    // Sector s's start is sector 0's instant −s·τ: sample −s·samples·EO/N (mod samples).
    const long k = samples > 0 ? ((-s * (shift / ns)) % samples + samples) % samples : 0;
    for (int c = 0; c < nc; ++c) {
      const ContactHistory& h = histories[static_cast<size_t>(c)];
      const double mu_n = sector.contacts[static_cast<size_t>(c)].mu * h.normal[k];
      double a = s == 0 ? contact_alpha[c] : (mu_n > 0.0 ? h.tangential[k] / mu_n : 0.0);
      out[s * nc + c] = std::clamp(a, -1.0, 1.0);
    }
  }
  return out;
}

Eigen::VectorXd SpreadOverRing(const Model& sector, const Eigen::VectorXd& x, int harmonics) {
  const int n = sector.num_dofs(), ns = sector.cyclic.sectors, nh = 2 * harmonics + 1;
  if (harmonics < 1 || x.size() != static_cast<Eigen::Index>(nh) * n) {
    throw std::invalid_argument("SpreadOverRing: x must hold (2H + 1) x " + std::to_string(n) +
                                " sector coefficients, got " + std::to_string(x.size()));
  }
  Eigen::VectorXd ring(static_cast<Eigen::Index>(nh) * n * ns);
  for (int s = 0; s < ns; ++s) {
    for (int d = 0; d < n; ++d) {
      ring[s * n + d] = x[d];
      for (int h = 1; h <= harmonics; ++h) {
        double a = x[(2 * h - 1) * n + d], b = x[2 * h * n + d];
        RotateHarmonic(h * s * sector.cyclic.phase(), &a, &b);
        ring[(2 * h - 1) * n * ns + s * n + d] = a;
        ring[2 * h * n * ns + s * n + d] = b;
      }
    }
  }
  return ring;
}

Eigen::VectorXd CyclicNaturalFrequencies(const Model& sector, int nodal_diameter, bool stick) {
  RequireCyclic(sector, "CyclicNaturalFrequencies");
  if (nodal_diameter < 0 || nodal_diameter > sector.cyclic.sectors / 2) {
    throw std::invalid_argument("CyclicNaturalFrequencies: nodal diameter must lie in 0.." +
                                std::to_string(sector.cyclic.sectors / 2) + ", got " +
                                std::to_string(nodal_diameter));
  }
  const int n = sector.num_dofs();
  Eigen::MatrixXcd k = sector.stiffness.cast<std::complex<double>>();
  if (stick) {
    // The stick springs' real block form at one harmonic whose delay is the nodal diameter's
    // phase: [[X, Y], [−Y, X]] is the complex Hermitian X + iY on the phasors a − ib.
    Model at_nd = sector;
    const double theta = 2.0 * std::numbers::pi * nodal_diameter / sector.cyclic.sectors;
    for (Contact& c : at_nd.contacts) {
      if (c.cyclic()) c.phase_b = theta;
    }
    const Eigen::MatrixXd ks = ContactStickStiffness(at_nd, 1);
    k.real() += ks.topLeftCorner(n, n);
    k.imag() += ks.topRightCorner(n, n);
  }
  const Eigen::MatrixXcd m = sector.mass.cast<std::complex<double>>();
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXcd> eig(k, m, Eigen::EigenvaluesOnly);
  if (eig.info() != Eigen::Success) {
    throw std::invalid_argument(
        "CyclicNaturalFrequencies: the eigenproblem failed (M not "
        "positive definite?)");
  }
  Eigen::VectorXd f = eig.eigenvalues();
  for (int i = 0; i < n; ++i) f[i] = std::sqrt(std::max(f[i], 0.0)) / (2.0 * std::numbers::pi);
  return f;
}

}  // namespace fricrom
