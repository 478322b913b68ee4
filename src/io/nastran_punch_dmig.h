// DMIG matrices and the EXTRN DOF set of the Nastran punch reader (nastran_punch.cpp): the
// entries the card parser collects, and their assembly into FeMatrix (nastran_punch_dmig.cpp).
// Private to src/io.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "fricrom/fe_model.h"

namespace fricrom::punch {

struct DmigEntry {
  DofId row, col;
  double a = 0, b = 0;
  bool b_given = false;
  size_t line = 0;
};

// One DMIG matrix as read: its header card fields and the entries of its column cards.
struct Dmig {
  std::string name;
  bool has_header = false;
  size_t header_line = 0;
  size_t first_line = 0;
  int64_t ifo = 0, tin = 0, tout = 0, polar = 0, ncol = 0;
  std::vector<DmigEntry> entries;
};

// The EXTRN DOFs sorted (DofLess), each with its position in the EXTRN order, for look-ups.
using ExtrnSorted = std::vector<std::pair<DofId, size_t>>;

// Sorts the EXTRN DOFs (`lines`: the line of each); fails on a DOF listed twice.
ExtrnSorted SortExtrn(const std::string& path, const std::vector<DofId>& extrn,
                      const std::vector<size_t>& lines);

// Assembles DMIG `d` in the storage `options` asks for. A DOF set of d inside the EXTRN set
// takes the EXTRN order (superelement matrices).
FeMatrix BuildDmig(const std::string& path, const Dmig& d, const std::vector<DofId>& extrn,
                   const ExtrnSorted& extrn_sorted, const FeReadOptions& options);

// A node set card (SET1, ASET, ASET1): its grid ids as ranges [first, last].
struct SetCard {
  std::string name;
  std::vector<std::pair<int64_t, int64_t>> ranges;
  size_t line = 0;
};

// The node sets of the set cards (model->nodes read): sets of one name (ASET over several cards)
// merge; an id listed singly is kept even without a GRID in the file, a THRU range keeps the
// file's grids inside it (a wide range allocates nothing).
void BuildNodeSets(const std::vector<SetCard>& sets, FeModel* model);

}  // namespace fricrom::punch
