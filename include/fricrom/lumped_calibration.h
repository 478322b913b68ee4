// A lumped 3-blade / 2-damper case (schema fricrom-case-1, the paper's model) calibrated from an
// FE cascade assembly, so the two can be compared on the same inputs (`fricrom lump`).
//
// Route (docs/lumped-vs-fe.md): the lumped plane is the FE circumferential-radial plane (lumped
// x = FE `circumferential`, lumped y = FE `radial` component). Each blade becomes a point mass
// that carries its calibration mode j (the blade mode nearest the case's frequency range):
//   - φ_j M-normalised on the blade alone (clamped root, no contacts); p_c, p_r = mean
//     circumferential / radial displacement of the blade's contact nodes;
//   - circumferential: modal mass m = 1/p_c², stiffness ω_j² m, damping 2 ζ_j ω_j m with
//     ζ_j = φ_jᵀCφ_j / (2ω_j);
//   - radial: the static stiffness k_r of the mean radial platform displacement, 1/(wᵀK⁻¹w), and
//     the mass that makes it resonate at the mode adding most to that flexibility (largest
//     p_r²/ω²), damped with the same ζ_j;
//   - a harmonic load f on the blade becomes the force φ_jᵀf / p_c on its platform;
//   - the response point moves s = |φ_j(response) / p_c| times the response blade's platform.
// Each damper is rigid: mass rᵀMr and grounding rᵀKr for the rigid translation r, its static
// load rᵀf₀ (the centrifugal preload). Each interface is one lumped contact: kn summed over its
// node pairs, kt summed over its in-plane laws, μ their kn-weighted mean, the wedge angle θ and
// the face from the in-plane normal. Every DOF is then scaled by s (masses and stiffnesses /s²,
// forces /s), exactly, so `blade.x` of the response blade reads the FE response point's amplitude.
#pragma once

#include <string>
#include <vector>

#include "fricrom/case_file.h"

namespace fricrom {

struct LumpOptions {
  int circumferential = 1;  // FE component (0 x, 1 y, 2 z) that becomes the lumped x
  int radial = 2;           // FE component that becomes the lumped y (dampers are pushed +y)
  bool IsValid(std::string* error) const;
};

struct LumpedBlade {
  std::string name;
  int mode = -1;                   // calibration mode (0-based, ascending frequency)
  double mode_hz = 0.0;            // its frequency, blade alone [Hz]
  int platform_nodes = 0;          // contact nodes that define the platform motion
  double modal_mass = 0.0;         // 1/p_c² [kg], platform-referenced
  double k_circumferential = 0.0;  // [N/m], platform-referenced
  double k_radial = 0.0;           // [N/m], static
  double radial_mass = 0.0;        // [kg]: k_radial resonates at radial_mode_hz
  int radial_mode = -1;            // the mode adding most to the radial platform flexibility
  double radial_mode_hz = 0.0;
  double damping_ratio = 0.0;               // ζ_j
  double force_cos = 0.0, force_sin = 0.0;  // harmonic-1 platform force [N]
};

struct LumpedDamper {
  std::string name;
  double mass = 0.0;              // [kg]
  double ground_stiffness = 0.0;  // [N/m] (translation)
  double preload = 0.0;           // [N] along the lumped +y
};

struct LumpedContact {
  std::string name;  // the FE interface
  std::string damper, counterpart;
  bool left_face = true;
  double theta = 0.0;  // wedge base angle [rad]
  double kn = 0.0, kt = 0.0, mu = 0.0;
  int pairs = 0;
};

struct LumpedCalibration {
  std::vector<LumpedBlade> blades;  // in the order of the FE case
  std::vector<LumpedDamper> dampers;
  std::vector<LumpedContact> contacts;
  std::string response_blade;
  double response_scale = 1.0;  // s: |response point / platform| in the response blade's mode
  std::string toml;             // the lumped case file (fricrom-case-1), commented, SI units
};

// Throws CaseError when the assembly is not a cascade of blades and dampers that the lumped model
// can represent (no blade or damper bodies, a contact between two blades, a response outside the
// blades, an interface whose normal does not push the damper radially outward, ...).
LumpedCalibration CalibrateLumped(const Case& fe_case, const LumpOptions& options = {});

}  // namespace fricrom
