// The host's vector forms of the shared row math (kernels/vec_math.h, under GCC) against the
// scalar forms that OpenCL C compiles: the same bits, so that the host's solve stays the serial
// reference of the device's.
#include "vec_math.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

namespace {

uint32_t bitsOf(float f) {
    uint32_t u;
    std::memcpy(&u, &f, sizeof u);
    return u;
}

// Floats of every kind a row holds: zeros of both signs, subnormals, infinities, NaN (the w lanes
// carry payloads such as an unbounded limit), and values over many magnitudes.
std::vector<float> sampleFloats() {
    const float inf = std::numeric_limits<float>::infinity();
    std::vector<float> v = {0.0f, -0.0f, 1.0f, -1.0f, 1e-40f, -1e-40f, inf, -inf,
                            std::numeric_limits<float>::quiet_NaN(), 3.4e38f, -3.4e38f, 1e-30f};
    std::mt19937 rng(20261127u);
    std::uniform_real_distribution<float> mantissa(-1.0f, 1.0f);
    std::uniform_int_distribution<int> exponent(-30, 30);
    for (int i = 0; i < 400; ++i) v.push_back(std::ldexp(mantissa(rng), exponent(rng)));
    return v;
}

}  // namespace

TEST_CASE("the host's vector sum and mask give the scalar forms' bits", "[vec-math]") {
    const std::vector<float> f = sampleFloats();
    std::mt19937 rng(7u);
    std::uniform_int_distribution<size_t> pick(0, f.size() - 1);
    int compared = 0;
    for (int i = 0; i < 20000; ++i) {
        const btoclFloat4 a{f[pick(rng)], f[pick(rng)], f[pick(rng)], f[pick(rng)]};
        // btoclSum3: x + y + z in that order.
        const float scalar = (a.x + a.y) + a.z;
        const float vector = btoclSum3(a);
        if (std::isnan(scalar)) {
            REQUIRE(std::isnan(vector));  // which NaN an add keeps is the instruction's choice
        } else {
            REQUIRE(bitsOf(vector) == bitsOf(scalar));
            ++compared;
        }
        // btoclXyz: x, y, z as they are (NaN payloads too), w +0.
        const btoclFloat4 m = btoclXyz(a);
        REQUIRE(bitsOf(m.x) == bitsOf(a.x));
        REQUIRE(bitsOf(m.y) == bitsOf(a.y));
        REQUIRE(bitsOf(m.z) == bitsOf(a.z));
        REQUIRE(bitsOf(m.w) == bitsOf(0.0f));
    }
    CHECK(compared > 15000);  // most sums are numbers, compared to the bit
}
