#include "fricrom/lumped_calibration.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <iomanip>
#include <map>
#include <set>
#include <sstream>

#include "fricrom/units.h"

namespace fricrom {
namespace {

const char* kAxis[] = {"x", "y", "z"};

[[noreturn]] void Fail(const Case& c, const std::string& what) {
  throw CaseError(c.source + ": lump: " + what);
}

// One body of the assembly: its DOFs (indices into the model) and their translation component.
struct BodyDofs {
  std::string name;
  bool blade = false;
  std::vector<int> dofs;
  std::vector<int> component;  // 0 x, 1 y, 2 z; −1 for modal or rotational DOFs
  std::map<int, int> local;    // model DOF -> position in dofs
};

int ComponentOf(const std::string& dof_name) {
  const size_t dot = dof_name.rfind('.');
  const std::string c = dot == std::string::npos ? "" : dof_name.substr(dot + 1);
  for (int k = 0; k < 3; ++k) {
    if (c == kAxis[k]) return k;
  }
  return -1;
}

std::vector<BodyDofs> SplitBodies(const Case& c) {
  const Model& m = c.model;
  const std::set<int> free(m.free_dofs.begin(), m.free_dofs.end());
  std::vector<BodyDofs> bodies;
  std::map<std::string, size_t> index;
  for (int d = 0; d < m.num_dofs(); ++d) {
    const std::string& name = m.dof_names[static_cast<size_t>(d)];
    const std::string body = name.substr(0, name.find('.'));
    auto [it, added] = index.try_emplace(body, bodies.size());
    if (added) bodies.push_back(BodyDofs{body, free.count(d) > 0, {}, {}, {}});
    BodyDofs& b = bodies[it->second];
    b.local[d] = static_cast<int>(b.dofs.size());
    b.dofs.push_back(d);
    b.component.push_back(ComponentOf(name));
  }
  return bodies;
}

Eigen::VectorXd Restrict(const Eigen::VectorXd& v, const BodyDofs& b) {
  Eigen::VectorXd r(static_cast<Eigen::Index>(b.dofs.size()));
  for (size_t i = 0; i < b.dofs.size(); ++i) r[static_cast<Eigen::Index>(i)] = v[b.dofs[i]];
  return r;
}

// Unit rigid translation of a body along `component` (exact for Craig-Bampton bodies: the
// constraint modes carry rigid motion of the boundary into the interior, modal amplitudes 0).
Eigen::VectorXd RigidTranslation(const BodyDofs& b, int component) {
  Eigen::VectorXd r = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(b.dofs.size()));
  for (size_t i = 0; i < b.dofs.size(); ++i)
    r[static_cast<Eigen::Index>(i)] = b.component[i] == component;
  return r;
}

// Mean displacement of the blade's contact nodes along `component`, as weights on its DOFs.
Eigen::VectorXd PlatformWeights(const Case& c, const BodyDofs& b, int component, int* nodes) {
  std::set<int> dofs;
  for (const Contact& ct : c.model.contacts) {
    for (const std::vector<int>* side : {&ct.dofs_a, &ct.dofs_b}) {
      if (side->size() == 3 && b.local.count((*side)[static_cast<size_t>(component)])) {
        dofs.insert(b.local.at((*side)[static_cast<size_t>(component)]));
      }
    }
  }
  Eigen::VectorXd w = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(b.dofs.size()));
  for (const int i : dofs) w[i] = 1.0 / static_cast<double>(dofs.size());
  *nodes = static_cast<int>(dofs.size());
  return w;
}

LumpedBlade CalibrateBlade(const Case& c, const BodyDofs& b, const LumpOptions& o,
                           Eigen::VectorXd* mode_shape) {
  const Model& m = c.model;
  LumpedBlade out;
  out.name = b.name;
  const Eigen::MatrixXd k = m.stiffness(b.dofs, b.dofs), mass = m.mass(b.dofs, b.dofs);
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(k, mass);
  if (eig.info() != Eigen::Success || !(eig.eigenvalues()[0] > 0.0)) {
    Fail(c, "blade '" + b.name + "' alone has no positive-definite modes (is its root clamped?)");
  }
  // The calibration mode: the blade mode nearest the case's frequency range (its centre).
  const double centre = 0.5 * (c.analysis.freq_min_hz + c.analysis.freq_max_hz);
  Eigen::Index j = 0;
  for (Eigen::Index i = 0; i < eig.eigenvalues().size(); ++i) {
    if (std::abs(HzFromEigenvalue(eig.eigenvalues()[i]) - centre) <
        std::abs(HzFromEigenvalue(eig.eigenvalues()[j]) - centre)) {
      j = i;
    }
  }
  const Eigen::VectorXd phi = eig.eigenvectors().col(j);
  const double omega = std::sqrt(eig.eigenvalues()[j]);
  int nodes_c = 0, nodes_r = 0;
  const Eigen::VectorXd wc = PlatformWeights(c, b, o.circumferential, &nodes_c);
  const Eigen::VectorXd wr = PlatformWeights(c, b, o.radial, &nodes_r);
  if (nodes_c == 0 || nodes_r == 0) Fail(c, "blade '" + b.name + "' has no contact nodes");
  const double pc = wc.dot(phi);
  if (!(std::abs(pc) > 1e-12 * phi.cwiseAbs().maxCoeff())) {
    Fail(c, "the platform of blade '" + b.name + "' does not move circumferentially in its mode " +
                std::to_string(j + 1) + " at " + std::to_string(HzFromEigenvalue(omega * omega)) +
                " Hz");
  }
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(k);
  const double flex_r = wr.dot(ldlt.solve(wr));
  if (ldlt.info() != Eigen::Success || !(flex_r > 0.0)) {
    Fail(c, "blade '" + b.name + "' is not fixed radially (its stiffness matrix is singular)");
  }
  out.mode = static_cast<int>(j);
  out.mode_hz = Hz(omega);
  out.platform_nodes = nodes_c;
  out.modal_mass = 1.0 / (pc * pc);
  out.k_circumferential = omega * omega * out.modal_mass;
  out.k_radial = 1.0 / flex_r;
  // Radial mass: the static radial stiffness resonates at the frequency of the mode that adds most
  // to the radial platform flexibility (largest p_r²/ω²), not at a spurious low frequency.
  Eigen::Index jr = 0;
  double best = -1.0;
  for (Eigen::Index i = 0; i < eig.eigenvalues().size(); ++i) {
    const double pr = wr.dot(eig.eigenvectors().col(i));
    if (pr * pr / eig.eigenvalues()[i] > best) {
      best = pr * pr / eig.eigenvalues()[i];
      jr = i;
    }
  }
  out.radial_mode = static_cast<int>(jr);
  out.radial_mode_hz = HzFromEigenvalue(eig.eigenvalues()[jr]);
  out.radial_mass = out.k_radial / eig.eigenvalues()[jr];
  out.damping_ratio = phi.dot(m.damping(b.dofs, b.dofs) * phi) / (2.0 * omega);
  for (const HarmonicLoad& l : m.loads) {
    const Eigen::VectorXd fc = Restrict(l.cos, b);
    const Eigen::VectorXd fs = l.harmonic > 0 ? Restrict(l.sin, b) : Eigen::VectorXd();
    if (l.harmonic == 1) {
      out.force_cos += phi.dot(fc) / pc;
      out.force_sin += phi.dot(fs) / pc;
    } else if (fc.cwiseAbs().maxCoeff() > 0.0 || (fs.size() && fs.cwiseAbs().maxCoeff() > 0.0)) {
      Fail(c, "blade '" + b.name + "' carries a load at harmonic " + std::to_string(l.harmonic) +
                  ": the lumped blade represents only its first-harmonic forcing");
    }
  }
  *mode_shape = phi / pc;  // response-point motion per unit platform motion
  return out;
}

LumpedDamper CalibrateDamper(const Case& c, const BodyDofs& b, const LumpOptions& o) {
  const Model& m = c.model;
  const Eigen::VectorXd rc = RigidTranslation(b, o.circumferential);
  const Eigen::VectorXd rr = RigidTranslation(b, o.radial);
  LumpedDamper d;
  d.name = b.name;
  const Eigen::MatrixXd mass = m.mass(b.dofs, b.dofs);
  d.mass = rc.dot(mass * rc);
  if (!(d.mass > 0.0)) Fail(c, "damper '" + b.name + "' has no translational mass");
  const Eigen::MatrixXd k = m.stiffness(b.dofs, b.dofs);
  d.ground_stiffness = std::max(rc.dot(k * rc), rr.dot(k * rr));
  for (const HarmonicLoad& l : m.loads) {
    const Eigen::VectorXd f = Restrict(l.cos, b);
    if (l.harmonic == 0) {
      d.preload += rr.dot(f);
      if (std::abs(rc.dot(f)) > 1e-9 * std::abs(rr.dot(f))) {
        Fail(c, "damper '" + b.name + "' has a static circumferential load");
      }
    } else if (f.cwiseAbs().maxCoeff() > 0.0 || Restrict(l.sin, b).cwiseAbs().maxCoeff() > 0.0) {
      Fail(c, "damper '" + b.name + "' carries a harmonic load (lumped dampers are not excited)");
    }
  }
  return d;
}

std::vector<LumpedContact> LumpContacts(const Case& c, const std::vector<BodyDofs>& bodies,
                                        const LumpOptions& o) {
  const Model& m = c.model;
  if (c.contact_interface.size() != m.contacts.size()) {
    Fail(c, "the contacts must come from [[interfaces]] (one lumped contact per interface)");
  }
  auto body_of = [&](int dof) -> const BodyDofs* {
    for (const BodyDofs& b : bodies) {
      if (b.local.count(dof)) return &b;
    }
    return nullptr;
  };
  const int axial = 3 - o.circumferential - o.radial;
  std::vector<LumpedContact> out(c.interface_names.size());
  std::vector<double> mu_kn(out.size(), 0.0);
  std::vector<std::set<std::pair<int, int>>> pairs(out.size());
  for (size_t ci = 0; ci < m.contacts.size(); ++ci) {
    const Contact& ct = m.contacts[ci];
    if (ct.normal.size() != 3 || ct.dofs_a.size() != 3 || ct.dofs_b.size() != 3) {
      Fail(c, "contact '" + ct.name + "' is not a 3D node pair");
    }
    const int itf = c.contact_interface[ci];
    LumpedContact& lc = out[static_cast<size_t>(itf)];
    lc.name = c.interface_names[static_cast<size_t>(itf)];
    const BodyDofs* a = body_of(ct.dofs_a[0]);
    const BodyDofs* b = body_of(ct.dofs_b[0]);
    if (a == nullptr || b == nullptr || a->blade == b->blade) {
      Fail(c, "interface '" + lc.name + "' must join a damper and a blade");
    }
    const double sign = a->blade ? -1.0 : 1.0;  // the normal from the damper into the blade
    lc.damper = a->blade ? b->name : a->name;
    lc.counterpart = a->blade ? a->name : b->name;
    const double nc = sign * ct.normal[o.circumferential], nr = sign * ct.normal[o.radial];
    if (std::abs(ct.normal[axial]) > 1e-6 || !(nr > 0.0) || std::abs(nc) < 1e-6) {
      Fail(c, "interface '" + lc.name + "' has a normal the lumped wedge cannot represent (it " +
                  "must lie in the circumferential-radial plane and push the damper outward)");
    }
    lc.left_face = nc < 0.0;
    lc.theta = std::atan2(std::abs(nc), nr);
    lc.kn += ct.kn;  // the laws of one pair share its normal gap: their kn add to the pair's
    pairs[static_cast<size_t>(itf)].emplace(ct.dofs_a[0], ct.dofs_b[0]);
    if (std::abs(ct.tangent[axial]) < 1e-6) {  // an in-plane law
      lc.kt += ct.kt;
      mu_kn[static_cast<size_t>(itf)] += ct.mu * ct.kn;
    }
  }
  for (size_t i = 0; i < out.size(); ++i) {
    out[i].pairs = static_cast<int>(pairs[i].size());
    if (!(out[i].kt > 0.0)) Fail(c, "interface '" + out[i].name + "' has no in-plane friction");
    out[i].mu = mu_kn[i] / out[i].kn;
  }
  return out;
}

std::string Identifier(const std::string& s) {
  std::string id = s;
  for (char& ch : id) {
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  }
  return id;
}

// A TOML basic-string body: quotes and backslashes escaped, control characters as spaces.
std::string Escaped(const std::string& s) {
  std::string out;
  for (const char ch : s) {
    if (ch == '"' || ch == '\\') {
      out += '\\';
      out += ch;
    } else if (static_cast<unsigned char>(ch) < 0x20) {
      out += ' ';
    } else {
      out += ch;
    }
  }
  return out;
}

std::string WriteToml(const Case& c, const LumpedCalibration& l, const LumpOptions& o) {
  std::ostringstream t;
  t << std::setprecision(10);
  t << "# fricrom case: lumped 3-blade / 2-damper model calibrated from the FE assembly\n"
    << "# " << Escaped(c.source) << " by `fricrom lump` (route: docs/lumped-vs-fe.md).\n"
    << "# Units: SI (m, kg, s, N, N/m, N s/m, rad); frequencies in Hz. Lumped x = FE "
    << kAxis[o.circumferential] << " (circumferential), lumped y = FE " << kAxis[o.radial]
    << " (radial).\n"
    << "# Every DOF is scaled by s (masses, stiffnesses, damping / s^2, forces / s), so "
    << l.response_blade << ".x\n# reads the amplitude of the FE response point; the "
    << "parameters hold the platform-referenced values.\n\n"
    << "schema = \"fricrom-case-1\"\nunits = \"SI\"\nname = \"" << Escaped(c.name) << "-lumped\"\n"
    << "description = \"lumped model of " << Escaped(c.name)
    << " (fricrom lump)\"\n\n[parameters]\n"
    << "s = " << l.response_scale << "  # |response point / platform circumferential motion| of "
    << l.response_blade << " in its calibration mode\n";
  for (const LumpedBlade& b : l.blades) {
    const std::string p = Identifier(b.name);
    t << "m_" << p << " = " << b.modal_mass << "  # [kg] modal mass at the platform, mode "
      << b.mode + 1 << " (" << b.mode_hz << " Hz, " << b.platform_nodes << " contact nodes)\n"
      << "kc_" << p << " = " << b.k_circumferential << "  # [N/m] circumferential, (2 pi f)^2 m\n"
      << "kr_" << p << " = " << b.k_radial << "  # [N/m] radial, static\n"
      << "mr_" << p << " = " << b.radial_mass << "  # [kg] radial mass: kr resonates at mode "
      << b.radial_mode + 1 << " (" << b.radial_mode_hz << " Hz)\n"
      << "zeta_" << p << " = " << b.damping_ratio << "  # modal damping ratio of that mode\n"
      << "F_" << p << " = " << b.force_cos << "  # [N] harmonic force (cos) at the platform\n";
  }
  for (const LumpedDamper& d : l.dampers) {
    const std::string p = Identifier(d.name);
    t << "m_" << p << " = " << d.mass << "  # [kg] rigid mass\n"
      << "kg_" << p << " = " << d.ground_stiffness << "  # [N/m] grounding\n"
      << "P_" << p << " = " << d.preload << "  # [N] static (centrifugal) load, radially out\n";
  }
  for (const LumpedContact& ct : l.contacts) {
    const std::string p = Identifier(ct.name);
    t << "kn_" << p << " = " << ct.kn << "  # [N/m] summed over " << ct.pairs << " node pairs\n"
      << "kt_" << p << " = " << ct.kt << "  # [N/m] in-plane laws summed\n"
      << "mu_" << p << " = " << ct.mu << "  # kn-weighted friction coefficient\n"
      << "theta_" << p << " = " << ct.theta << "  # [rad] wedge base angle from the face normal\n";
  }
  for (const LumpedBlade& b : l.blades) {
    const std::string p = Identifier(b.name);
    t << "\n[[bodies]]\nname = \"" << b.name << "\"\nkind = \"blade\"\nmass = \"m_" << p
      << "/s^2\"\nmass_y = \"mr_" << p << "/s^2\"\nground_stiffness_x = \"kc_" << p
      << "/s^2\"\nground_stiffness_y = \"kr_" << p << "/s^2\"\nground_damping_x = \"2*zeta_" << p
      << "*sqrt(kc_" << p << "*m_" << p << ")/s^2\"\nground_damping_y = \"2*zeta_" << p
      << "*sqrt(kr_" << p << "*mr_" << p << ")/s^2\"\n";
  }
  for (const LumpedDamper& d : l.dampers) {
    const std::string p = Identifier(d.name);
    t << "\n[[bodies]]\nname = \"" << d.name << "\"\nkind = \"damper\"\nmass = \"m_" << p
      << "/s^2\"\nground_stiffness = \"kg_" << p << "/s^2\"\n";
  }
  for (const LumpedContact& ct : l.contacts) {
    const std::string p = Identifier(ct.name);
    t << "\n[[contacts]]\nname = \"" << ct.name << "\"\ndamper = \"" << ct.damper
      << "\"\ncounterpart = \"" << ct.counterpart << "\"\nface = \""
      << (ct.left_face ? "left" : "right") << "\"\ntheta = \"theta_" << p << "\"\nkn = \"kn_" << p
      << "/s^2\"\nkt = \"kt_" << p << "/s^2\"\nmu = \"mu_" << p << "\"\n";
  }
  for (const LumpedDamper& d : l.dampers) {
    t << "\n[[loads]]\ndof = \"" << d.name << ".y\"\nharmonic = 0\ncos = \"P_" << Identifier(d.name)
      << "/s\"\n";
  }
  for (const LumpedBlade& b : l.blades) {
    if (b.force_cos == 0.0 && b.force_sin == 0.0) continue;
    t << "\n[[loads]]\ndof = \"" << b.name << ".x\"\nharmonic = 1\ncos = \"F_" << Identifier(b.name)
      << "/s\"\nsin = \"" << b.force_sin << "/s\"\n";
  }
  t << "\n[response]\ndof = \"" << l.response_blade
    << ".x\"  # = the FE response point (scaled by s)\n"
    << "\n[analysis]\nharmonics = " << c.analysis.harmonics
    << "\nsamples_per_period = " << c.analysis.samples_per_period
    << "\nfreq_min_hz = " << c.analysis.freq_min_hz << "\nfreq_max_hz = " << c.analysis.freq_max_hz
    << "\n";
  return t.str();
}

}  // namespace

bool LumpOptions::IsValid(std::string* error) const {
  if (circumferential < 0 || circumferential > 2 || radial < 0 || radial > 2 ||
      circumferential == radial) {
    *error = "LumpOptions: circumferential and radial must be two different components in 0..2";
    return false;
  }
  return true;
}

LumpedCalibration CalibrateLumped(const Case& fe, const LumpOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument(error);
  const std::vector<BodyDofs> bodies = SplitBodies(fe);
  LumpedCalibration out;
  Eigen::VectorXd response_shape;
  for (const BodyDofs& b : bodies) {
    if (!b.blade) {
      out.dampers.push_back(CalibrateDamper(fe, b, options));
      continue;
    }
    Eigen::VectorXd shape;
    out.blades.push_back(CalibrateBlade(fe, b, options, &shape));
    if (b.local.count(fe.model.response_dof)) {
      out.response_blade = b.name;
      out.response_scale = std::abs(shape[b.local.at(fe.model.response_dof)]);
    }
  }
  if (out.blades.empty() || out.dampers.empty()) Fail(fe, "needs blade and damper bodies");
  if (out.response_blade.empty()) Fail(fe, "the response DOF must lie on a blade");
  if (!(out.response_scale > 0.0)) Fail(fe, "the response point does not move in its blade's mode");
  out.contacts = LumpContacts(fe, bodies, options);
  // Body and interface names become lumped DOF, contact and parameter names.
  auto plain = [](const std::string& n) {
    return !n.empty() && std::all_of(n.begin(), n.end(), [](char ch) {
      return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '-';
    });
  };
  for (const BodyDofs& b : bodies) {
    if (!plain(b.name))
      Fail(fe, "body name '" + b.name + "' is not a plain name (letters, digits, _ -)");
  }
  for (const LumpedContact& ct : out.contacts) {
    if (!plain(ct.name))
      Fail(fe, "interface name '" + ct.name + "' is not a plain name (letters, digits, _ -)");
  }
  out.toml = WriteToml(fe, out, options);
  return out;
}

}  // namespace fricrom
