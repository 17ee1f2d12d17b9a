// Vector math on btoclFloat4 that reads the same in OpenCL C and C++, so that row math written
// once (row_setup.h, row_solve.h) compiles for the device and for the host. OpenCL C has the
// operators built in; C++ gets them here, on the mirror struct of btocl_shared.h. Only x, y, z
// carry vectors; w is a payload lane (see the lane names in btocl_shared.h).
#ifndef BTOCL_VEC_MATH_H
#define BTOCL_VEC_MATH_H

#include "btocl_shared.h"

#ifdef __OPENCL_VERSION__
#define BTOCL_FLOAT4(x, y, z, w) ((float4)((x), (y), (z), (w)))
#define btoclSqrt sqrt
#define btoclFabs fabs
#else
#include <math.h>
#define BTOCL_FLOAT4(x, y, z, w) (btoclFloat4{(x), (y), (z), (w)})
#define btoclSqrt sqrtf
#define btoclFabs fabsf

#if defined(__GNUC__)
// The four lanes as one vector (GCC's vector extension), as a device compiler keeps them: the same
// operation in each lane as the scalar form, so the same bits, in a quarter of the instructions
// (the compiler leaves the scalar form scalar).
typedef float btoclVector4 __attribute__((vector_size(16)));
typedef int btoclIndex4 __attribute__((vector_size(16)));  // lane indices and masks
inline btoclVector4 btoclVec(btoclFloat4 a) { return btoclVector4{a.x, a.y, a.z, a.w}; }
inline btoclFloat4 btoclOf(btoclVector4 v) { return {v[0], v[1], v[2], v[3]}; }
inline btoclFloat4 operator+(btoclFloat4 a, btoclFloat4 b) { return btoclOf(btoclVec(a) + btoclVec(b)); }
inline btoclFloat4 operator-(btoclFloat4 a, btoclFloat4 b) { return btoclOf(btoclVec(a) - btoclVec(b)); }
inline btoclFloat4 operator-(btoclFloat4 a) { return btoclOf(-btoclVec(a)); }
inline btoclFloat4 operator*(btoclFloat4 a, btoclFloat4 b) { return btoclOf(btoclVec(a) * btoclVec(b)); }
inline btoclFloat4 operator*(btoclFloat4 a, float s) { return btoclOf(btoclVec(a) * s); }
// x + y + z with y and z moved down by shuffles: the lanes stay in registers (GCC took x through
// the stack to add it, a store and a reload in the solve's chain of rows).
inline float btoclSum3(btoclFloat4 a) {
    const btoclVector4 v = btoclVec(a);
    const btoclVector4 y = __builtin_shuffle(v, btoclIndex4{1, 1, 1, 1});
    const btoclVector4 z = __builtin_shuffle(v, btoclIndex4{2, 2, 2, 2});
    return ((v + y) + z)[0];
}
// The vector part, w cleared by a mask (GCC built it lane by lane from three loads).
inline btoclFloat4 btoclXyz(btoclFloat4 a) {
    const btoclIndex4 bits = (btoclIndex4)btoclVec(a) & btoclIndex4{-1, -1, -1, 0};
    return btoclOf((btoclVector4)bits);
}
#else
inline btoclFloat4 operator+(btoclFloat4 a, btoclFloat4 b) { return {a.x + b.x, a.y + b.y, a.z + b.z, a.w + b.w}; }
inline btoclFloat4 operator-(btoclFloat4 a, btoclFloat4 b) { return {a.x - b.x, a.y - b.y, a.z - b.z, a.w - b.w}; }
inline btoclFloat4 operator-(btoclFloat4 a) { return {-a.x, -a.y, -a.z, -a.w}; }
inline btoclFloat4 operator*(btoclFloat4 a, btoclFloat4 b) { return {a.x * b.x, a.y * b.y, a.z * b.z, a.w * b.w}; }
inline btoclFloat4 operator*(btoclFloat4 a, float s) { return {a.x * s, a.y * s, a.z * s, a.w * s}; }
#endif
inline btoclFloat4 operator*(float s, btoclFloat4 a) { return a * s; }
inline btoclFloat4& operator+=(btoclFloat4& a, btoclFloat4 b) { return a = a + b; }
inline btoclFloat4& operator*=(btoclFloat4& a, float s) { return a = a * s; }
#endif

#if defined(__OPENCL_VERSION__) || !defined(__GNUC__)
BTOCL_INLINE float btoclSum3(btoclFloat4 a) { return a.x + a.y + a.z; }
// The vector part, w cleared.
BTOCL_INLINE btoclFloat4 btoclXyz(btoclFloat4 v) { return BTOCL_FLOAT4(v.x, v.y, v.z, 0.0f); }
#endif
BTOCL_INLINE btoclFloat4 btoclZero4(void) { return BTOCL_FLOAT4(0.0f, 0.0f, 0.0f, 0.0f); }
// v's vector part with w set to a payload.
BTOCL_INLINE btoclFloat4 btoclWithW(btoclFloat4 v, float w) { return BTOCL_FLOAT4(v.x, v.y, v.z, w); }
BTOCL_INLINE float btoclDot3(btoclFloat4 a, btoclFloat4 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
BTOCL_INLINE btoclFloat4 btoclCross3(btoclFloat4 a, btoclFloat4 b) {
    return BTOCL_FLOAT4(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x, 0.0f);
}
BTOCL_INLINE float btoclLength3(btoclFloat4 v) { return btoclSqrt(btoclDot3(v, v)); }
// v / |v| as btVector3::normalize computes it (a multiply by the reciprocal length).
BTOCL_INLINE btoclFloat4 btoclNormalize3(btoclFloat4 v) { return btoclXyz(v) * (1.0f / btoclLength3(v)); }

// A 3x3 matrix given by its rows (btMatrix3x3's layout) times v.
BTOCL_INLINE btoclFloat4 btoclRowsTimes(btoclFloat4 row0, btoclFloat4 row1, btoclFloat4 row2, btoclFloat4 v) {
    return BTOCL_FLOAT4(btoclDot3(row0, v), btoclDot3(row1, v), btoclDot3(row2, v), 0.0f);
}

// Two unit axes orthogonal to unit n, by btPlaneSpace1's convention: p first, q = n x p.
BTOCL_INLINE void btoclPlaneSpace(btoclFloat4 n, btoclFloat4* p, btoclFloat4* q) {
    if (btoclFabs(n.z) > 0.70710678f) {
        const float a = n.y * n.y + n.z * n.z;
        const float k = 1.0f / btoclSqrt(a);
        *p = BTOCL_FLOAT4(0.0f, -n.z * k, n.y * k, 0.0f);
        *q = BTOCL_FLOAT4(a * k, -n.x * p->z, n.x * p->y, 0.0f);
    } else {
        const float a = n.x * n.x + n.y * n.y;
        const float k = 1.0f / btoclSqrt(a);
        *p = BTOCL_FLOAT4(-n.y * k, n.x * k, 0.0f, 0.0f);
        *q = BTOCL_FLOAT4(-n.z * p->y, n.z * p->x, a * k, 0.0f);
    }
}

#endif
