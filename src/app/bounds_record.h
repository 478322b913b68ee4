// A bound computation as JSON that reads back bit for bit (doubles in shortest round-trip form,
// NaN as null): the unit result that bound-curve journals record and MPI ranks send to rank 0.
#pragma once

#include <nlohmann/json.hpp>

#include "fricrom/bounds.h"
#include "fricrom/design.h"

namespace fricrom::app {

nlohmann::json BoundsRecord(const BoundsResult& b);
// Throws std::runtime_error naming the missing or mistyped key.
BoundsResult BoundsFromRecord(const nlohmann::json& j);

// A robustness point (a sweep value or NOA evaluation) the same way.
nlohmann::json RobustnessRecord(const RobustnessPoint& p);
RobustnessPoint RobustnessFromRecord(const nlohmann::json& j);

}  // namespace fricrom::app
