// Sensors in an order that keeps neighbours together: the exact direct sum takes them N at a
// time, and the shadow rays of neighbouring sensors towards one luminaire walk the BVH
// together. A grid handed over row by row puts N sensors of one long row in a packet; the
// Morton (Z) order over the sensors' bounding box a compact tile. Each sensor's lux does not
// depend on its neighbours, so the order changes the speed only.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace patina {

// Indices of points (n x 3) along the Morton curve through their bounding box, 10 bits an axis.
std::vector<uint32_t> morton_order(const float* points, size_t n);

}  // namespace patina
