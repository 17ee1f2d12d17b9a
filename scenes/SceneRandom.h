// A deterministic random number stream for scene builders (the same in every build and on every
// platform: the scenes must not depend on std::rand or a library's distributions).
#pragma once

#include <LinearMath/btVector3.h>

#include <algorithm>

namespace btscenes {

class SceneRandom {
public:
    explicit SceneRandom(unsigned seed) : m_state(seed * 2654435761u + 12345u) {}
    // A stream from its raw state rather than a seed (the benchmark's scenes were drawn so).
    static SceneRandom fromState(unsigned state) {
        SceneRandom r(0);
        r.m_state = state;
        return r;
    }
    btScalar uniform(btScalar lo = 0, btScalar hi = 1) {  // in [lo, hi)
        m_state = m_state * 1664525u + 1013904223u;
        return lo + (hi - lo) * btScalar((m_state >> 8) & 0xffffffu) / btScalar(16777216);
    }
    int below(int n) { return std::min(n - 1, int(uniform() * btScalar(n))); }
    btVector3 unitVector() {
        for (;;) {
            const btVector3 v(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
            if (v.length2() > btScalar(0.05) && v.length2() <= 1) return v.normalized();
        }
    }
    btVector3 vector(btScalar scale) { return btVector3(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)) * scale; }

private:
    unsigned m_state;
};

}  // namespace btscenes
