// Boundary DOFs of a Craig-Bampton reduction from the node sets of an FE model.
#include <algorithm>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <unordered_set>

#include "fricrom/reduction.h"

namespace fricrom {

BoundarySelection SelectBoundaryDofs(const FeModel& model, const FeMatrix& matrix,
                                     const std::vector<std::string>& set_names,
                                     const std::vector<int>& components) {
  if (matrix.row_dofs.empty()) {
    throw std::invalid_argument("matrix " + matrix.name +
                                " has no DOF map (node, component per row): boundary node sets "
                                "cannot be located; give the order of its rows (fe = {dofs = "
                                "...}, reduce --dofs): a CSV node,component or the EXTRN punch "
                                "of the superelement");
  }
  for (const int c : components) {
    if (c < 1 || c > 6) {
      throw std::invalid_argument("boundary component " + std::to_string(c) +
                                  ": expected 1..6 (x, y, z, rx, ry, rz)");
    }
  }
  // node -> its rows, component ascending.
  std::unordered_map<int64_t, std::vector<int>> rows_of_node;
  for (size_t r = 0; r < matrix.row_dofs.size(); ++r) {
    rows_of_node[matrix.row_dofs[r].node].push_back(static_cast<int>(r));
  }
  for (auto& [node, rows] : rows_of_node) {
    std::sort(rows.begin(), rows.end(), [&](int a, int b) {
      return matrix.row_dofs[a].component < matrix.row_dofs[b].component;
    });
  }
  BoundarySelection out;
  std::unordered_set<int64_t> taken;
  for (const std::string& name : set_names) {
    const NodeSet* set = model.FindNodeSet(name);
    if (!set) {
      std::string known;
      for (const NodeSet& s : model.node_sets) known += (known.empty() ? "" : ", ") + s.name;
      throw std::invalid_argument(
          "unknown node set '" + name + "' in " + model.source + " (sets in the model: " +
          (known.empty() ? std::string("none; the deck (.inp) defines them with *NSET") : known) +
          ")");
    }
    if (set->nodes.empty()) throw std::invalid_argument("node set " + set->name + " is empty");
    for (const int64_t node : set->nodes) {
      if (!taken.insert(node).second) continue;
      const auto it = rows_of_node.find(node);
      int found = 0;
      if (it != rows_of_node.end()) {
        for (const int r : it->second) {
          const int c = matrix.row_dofs[r].component;
          if (!components.empty() &&
              std::find(components.begin(), components.end(), c) == components.end()) {
            continue;
          }
          out.indices.push_back(r);
          out.dofs.push_back(matrix.row_dofs[r]);
          ++found;
        }
      }
      if (found == 0) {
        throw std::invalid_argument(
            "node " + std::to_string(node) + " of set " + set->name + " has " +
            (it == rows_of_node.end() ? std::string("no DOF")
                                      : std::string("none of the requested components")) +
            " in matrix " + matrix.name +
            " (constrained by *BOUNDARY, or not a node of the meshed model?)");
      }
      out.nodes.push_back(node);
    }
  }
  return out;
}

}  // namespace fricrom
