// What the exact direct illuminance measures at each point (render/lighting/direct_illuminance.h):
// planar sensors (horizontal, vertical at an azimuth, perpendicular to a surface) take the
// illuminance on their plane; cylindrical and semi-cylindrical ones EN 13201-3's vertical
// cylinders (python/patina/lighting/sensors.py says how; sensor_response_impl.h computes it).
#pragma once

#include <cstddef>
#include <cstdint>

namespace patina {

enum class SensorKind : uint8_t { Planar, Cylindrical, SemiCylindrical };

struct IlluminanceSensors {
    SensorKind kind = SensorKind::Planar;
    const float* points = nullptr;   // count x 3
    // count x 3: planar, each plane's unit normal; semi-cylindrical, the horizontal unit
    // direction each half-cylinder faces; cylindrical, unread (may be null)
    const float* normals = nullptr;
    size_t count = 0;
};

}  // namespace patina
