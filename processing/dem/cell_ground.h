#pragma once
// What is known of a DEM cell's ground: seen (ground points in it), unseen (a DEM value
// reached from elsewhere) or estimated (no DEM value; an estimate for the terrain correction).
#include <cstdint>

namespace ts {

enum class CellGround : uint8_t { kSeen = 0, kUnseen = 1, kEstimated = 2 };

}  // namespace ts
