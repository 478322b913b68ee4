// Bladed disks in cyclic symmetry: one sector (its blade and damper) stands for the ring of N
// identical sectors under an engine-order (EO) travelling-wave load. Sector s's response is
// sector 0's delayed by s·φ/ω, φ = 2π·EO/N: harmonic h of the next sector is harmonic h of this
// one delayed by h·φ (nodal diameter h·EO folded into 0..N/2), harmonic 0 — the static state and
// with it α — is the same in every sector. A cyclic contact (Contact::phase_b, normal_b,
// tangent_b) couples a sector's node set to its neighbour's through that delay, so the harmonic
// balance keeps the size of one sector.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "fricrom/harmonic_balance.h"
#include "fricrom/model.h"

namespace fricrom {

// The explicit ring of a cyclic sector (sector.cyclic): N copies of its DOFs, each sector in its
// own rotated frame (so K, M, C repeat), its ordinary contacts per sector, each cyclic contact
// between sector s's side A and sector s+1's side B (directions normal / normal_b, no delay),
// the loads of sector s delayed by s·φ, the response DOF of sector 0; DOF names "s<k>.<name>".
// α: the sector's α shared by every sector, or (alpha_per_sector) one copy per sector, sector s's
// after sector s−1's. Throws std::invalid_argument for a model without cyclic symmetry.
Model ExpandCyclicRing(const Model& sector, bool alpha_per_sector = false);

// α is the tangential force at the start of the period over μN there (contact_law.h), an
// instant each sector of the ring meets at a different point of the travelling wave. The α of
// every contact of the explicit ring (ExpandCyclicRing's contact order) that puts the ring on a
// sector solution: sector 0 keeps the sector's α, sector s, whose period starts s·φ/ω later in
// the wave, takes T/(μN) of the sector's contact histories at that instant (0 where the contact
// is open). A contact stuck over the period carries its static tangential force — the same in
// every sector — through them. Throws std::invalid_argument unless samples_per_period·EO/N is
// whole (the instant must be a sample) and there is one history per contact.
Eigen::VectorXd RingContactAlpha(const Model& sector, const std::vector<ContactHistory>& histories,
                                 const Eigen::VectorXd& contact_alpha);

// The explicit ring's harmonic coefficients (ExpandCyclicRing's DOF order, harmonic-major as the
// balance's unknowns) of a sector solution x (the sector's DOFs at `harmonics`): sector s is
// sector 0 delayed by s·φ, harmonic h by h·s·φ. Throws std::invalid_argument unless x has
// (2·harmonics + 1)·num_dofs entries.
Eigen::VectorXd SpreadOverRing(const Model& sector, const Eigen::VectorXd& x, int harmonics);

// Natural frequencies [Hz] of the sector's linear part at nodal diameter nd (0..N/2): the
// cyclic contacts' stick springs coupled through the phase 2π·nd/N (stick = true), or without
// any contact (stick = false: then the sectors are uncoupled and every nodal diameter has the
// same frequencies). Ascending, one per sector DOF.
Eigen::VectorXd CyclicNaturalFrequencies(const Model& sector, int nodal_diameter, bool stick);

// The nodal diameter harmonic h of an engine-order load lives in: h·EO folded into 0..N/2.
int NodalDiameterOfHarmonic(const CyclicSymmetry& cyclic, int harmonic);

}  // namespace fricrom
