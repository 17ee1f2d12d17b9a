// Bullet's vectors to and from the kernels' float4 records.
#pragma once

#include "btocl_shared.h"

#include <LinearMath/btVector3.h>

#include <cmath>

namespace btocl {

inline btoclFloat4 toFloat4(const btVector3& v, float w = 0) { return {v.x(), v.y(), v.z(), w}; }
inline btVector3 toVector3(const btoclFloat4& f) { return btVector3(f.x, f.y, f.z); }
inline bool isFinite(const btVector3& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

}  // namespace btocl
