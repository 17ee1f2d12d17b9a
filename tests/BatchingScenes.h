// Constraint sets for the split and batching tests: per body a SplitBody, per touching pair a
// btoclConstraint at a point inside both bodies' boxes (as a contact point is). Body 0 is a static
// ground everywhere. Deterministic for a given seed.
#pragma once

#include "HostBatching.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <unordered_map>
#include <vector>

namespace btocl_test {

struct Vec3 {
    float x, y, z;
};

struct BatchScene {
    std::string name;
    std::vector<btoclConstraint> constraints;
    std::vector<btocl::SplitBody> bodies;
    std::vector<Vec3> centers;  // per body (the ground's is unused)
};

class SceneBuilder {
public:
    explicit SceneBuilder(std::string name) {
        m_scene.name = std::move(name);
        m_scene.bodies.push_back(btocl::SplitBody{0, false});  // body 0: the static ground
        m_scene.centers.push_back(Vec3{0, 0, 0});
    }
    int addBody(Vec3 c, float extent, bool dynamic = true) {
        m_scene.bodies.push_back(btocl::SplitBody{dynamic ? extent : 0, dynamic});
        m_scene.centers.push_back(c);
        return int(m_scene.bodies.size()) - 1;
    }
    void contactAt(int a, int b, Vec3 p) {
        btoclConstraint c{};
        c.position = btoclFloat4{p.x, p.y, p.z, 0};
        c.bodyA = a;
        c.bodyB = b;
        c.dynamicA = m_scene.bodies[size_t(a)].dynamic ? 1 : 0;
        c.dynamicB = m_scene.bodies[size_t(b)].dynamic ? 1 : 0;
        m_scene.constraints.push_back(c);
    }
    // A contact between two dynamic boxes: on the segment of centres, inside both boxes.
    void contact(int a, int b) {
        const Vec3 ca = center(a), cb = center(b);
        const float ea = extent(a), eb = extent(b);
        const float t = ea / (ea + eb);
        contactAt(a, b, Vec3{ca.x + (cb.x - ca.x) * t, ca.y + (cb.y - ca.y) * t, ca.z + (cb.z - ca.z) * t});
    }
    // A contact with the ground under the box (the ground is the plane z = 0).
    void groundContact(int a) {
        const Vec3 c = center(a);
        contactAt(0, a, Vec3{c.x, c.y, c.z - extent(a) * 0.5f});
    }
    Vec3 center(int a) const { return m_scene.centers[size_t(a)]; }
    float extent(int a) const { return m_scene.bodies[size_t(a)].extent; }
    BatchScene take() { return std::move(m_scene); }

private:
    BatchScene m_scene;
};

// Boxes (extents 0.6..1.2) at random in a slab, a contact between every two whose boxes overlap,
// and with the ground under the low ones: about 4 contacts per box.
inline BatchScene randomPile(int numBodies, unsigned seed, Vec3 offset = Vec3{0, 0, 0}) {
    SceneBuilder s("random pile of " + std::to_string(numBodies));
    std::mt19937 rng(seed);
    const float volume = float(numBodies) / 0.45f;
    const float side = std::cbrt(volume * 4.0f);  // a slab 4x wider than high
    std::uniform_real_distribution<float> xy(0, side), z(0.5f, 0.5f + side / 4.0f), ext(0.6f, 1.2f);
    std::vector<int> ids;
    for (int i = 0; i < numBodies; ++i) {
        const Vec3 c{xy(rng), xy(rng), z(rng)};
        ids.push_back(s.addBody(Vec3{c.x + offset.x, c.y + offset.y, c.z + offset.z}, ext(rng)));
    }
    // Pairs through a hash grid of unit cells (max extent 1.2: neighbours within 2 cells).
    auto cellOf = [&](const Vec3& c) {
        return std::array<int, 3>{int(std::floor((c.x - offset.x) / 1.2f)), int(std::floor((c.y - offset.y) / 1.2f)),
                                  int(std::floor((c.z - offset.z) / 1.2f))};
    };
    auto hashOf = [](const std::array<int, 3>& k) { return (long long)(k[0]) * 73856093LL ^ (long long)(k[1]) * 19349663LL ^ (long long)(k[2]) * 83492791LL; };
    std::unordered_map<long long, std::vector<int>> grid;
    for (int id : ids) grid[hashOf(cellOf(s.center(id)))].push_back(id);
    for (int a : ids) {
        const auto k = cellOf(s.center(a));
        std::vector<int> near;
        for (int dx = -1; dx <= 1; ++dx)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dz = -1; dz <= 1; ++dz) {
                    auto it = grid.find(hashOf({k[0] + dx, k[1] + dy, k[2] + dz}));
                    if (it != grid.end()) near.insert(near.end(), it->second.begin(), it->second.end());
                }
        std::sort(near.begin(), near.end());
        near.erase(std::unique(near.begin(), near.end()), near.end());
        for (int b : near) {
            if (b <= a) continue;
            const Vec3 ca = s.center(a), cb = s.center(b);
            const float reach = 0.5f * (s.extent(a) + s.extent(b));
            if (std::fabs(ca.x - cb.x) < reach && std::fabs(ca.y - cb.y) < reach && std::fabs(ca.z - cb.z) < reach)
                s.contact(a, b);
        }
        if (s.center(a).z - offset.z < s.extent(a)) s.groundContact(a);
    }
    return s.take();
}

// A 2D pyramid of unit boxes in the x-z plane: each box rests on two and touches its row neighbours.
inline BatchScene pyramid(int base) {
    SceneBuilder s("pyramid of base " + std::to_string(base));
    std::vector<std::vector<int>> rows;
    for (int r = 0; r < base; ++r) {
        std::vector<int> row;
        for (int i = 0; i < base - r; ++i) row.push_back(s.addBody(Vec3{float(i) + 0.5f * float(r), 0, float(r) + 0.5f}, 1));
        for (size_t i = 0; i < row.size(); ++i) {
            if (r == 0) s.groundContact(row[i]);
            else {
                s.contact(rows.back()[i], row[i]);
                s.contact(rows.back()[i + 1], row[i]);
            }
            if (i > 0) s.contact(row[i - 1], row[i]);
        }
        rows.push_back(row);
    }
    return s.take();
}

// A brick wall in the x-z plane: 2x1 bricks, odd rows shifted by half a brick.
inline BatchScene wall(int width, int height) {
    SceneBuilder s("wall " + std::to_string(width) + "x" + std::to_string(height));
    std::vector<std::vector<int>> rows;
    for (int r = 0; r < height; ++r) {
        std::vector<int> row;
        const float shift = (r % 2) ? 1.0f : 0.0f;
        for (int i = 0; i < width; ++i) row.push_back(s.addBody(Vec3{2.0f * float(i) + 1.0f + shift, 0, float(r) + 0.5f}, 2));
        for (int i = 0; i < width; ++i) {
            if (r == 0) s.groundContact(row[size_t(i)]);
            else {
                // Bricks below overlapping in x: i and i+1 (odd row) or i-1 and i (even row).
                const int lo = (r % 2) ? i : i - 1;
                for (int j = lo; j <= lo + 1; ++j)
                    if (j >= 0 && j < width) s.contact(rows.back()[size_t(j)], row[size_t(i)]);
            }
            if (i > 0) s.contact(row[size_t(i) - 1], row[size_t(i)]);
        }
        rows.push_back(row);
    }
    return s.take();
}

// A dense block of unit boxes, each touching its face and edge neighbours (9 pairs per box inside).
inline BatchScene denseBlock(int nx, int ny, int nz) {
    SceneBuilder s("dense block " + std::to_string(nx) + "x" + std::to_string(ny) + "x" + std::to_string(nz));
    auto id = [&](int x, int y, int z) { return 1 + (z * ny + y) * nx + x; };
    for (int z = 0; z < nz; ++z)
        for (int y = 0; y < ny; ++y)
            for (int x = 0; x < nx; ++x) s.addBody(Vec3{float(x) + 0.5f, float(y) + 0.5f, float(z) + 0.5f}, 1.02f);
    const int d[9][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {1, -1, 0}, {1, 0, 1}, {-1, 0, 1}, {0, 1, 1}, {0, -1, 1}};
    for (int z = 0; z < nz; ++z)
        for (int y = 0; y < ny; ++y)
            for (int x = 0; x < nx; ++x) {
                if (z == 0) s.groundContact(id(x, y, z));
                for (const auto& o : d) {
                    const int X = x + o[0], Y = y + o[1], Z = z + o[2];
                    if (X >= 0 && X < nx && Y >= 0 && Y < ny && Z < nz) s.contact(id(x, y, z), id(X, Y, Z));
                }
            }
    return s.take();
}

// A long chain of touching unit boxes along x, across many cells.
inline BatchScene chain(int n) {
    SceneBuilder s("chain of " + std::to_string(n));
    int prev = -1;
    for (int i = 0; i < n; ++i) {
        const int b = s.addBody(Vec3{float(i), 0, 0.5f}, 1);
        if (prev >= 0) s.contact(prev, b);
        prev = b;
    }
    return s.take();
}

// A dynamic plank (extent 60) on the ground carrying 100 unit boxes in a row that touch each other,
// beside a small pile so that the median body stays a unit box.
inline BatchScene plankWithBoxes() {
    SceneBuilder s("plank carrying 100 boxes");
    const int plank = s.addBody(Vec3{30, 0, 0.25f}, 60);
    s.contactAt(0, plank, Vec3{1, 0, 0});
    s.contactAt(0, plank, Vec3{59, 0, 0});
    int prev = -1;
    for (int i = 0; i < 100; ++i) {
        const int b = s.addBody(Vec3{0.55f + 0.6f * float(i), 0, 1.0f}, 0.6f);
        s.contactAt(plank, b, Vec3{s.center(b).x, 0, 0.5f});
        if (prev >= 0) s.contact(prev, b);
        prev = b;
    }
    return s.take();
}

// 300 unit boxes and 1500 random pairs among them, all contact points inside one cell.
inline BatchScene allInOneCell(unsigned seed) {
    SceneBuilder s("all bodies in one cell");
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> at(0, 0.4f);
    std::vector<int> ids;
    for (int i = 0; i < 300; ++i) ids.push_back(s.addBody(Vec3{at(rng), at(rng), at(rng)}, 1));
    std::uniform_int_distribution<int> pick(0, 299);
    for (int k = 0; k < 1500; ++k) {
        const int a = ids[size_t(pick(rng))], b = ids[size_t(pick(rng))];
        if (a != b) s.contactAt(a, b, Vec3{at(rng), at(rng), at(rng)});
    }
    return s.take();
}

// One unit box touched by 200 others; the contact points spread over the hub's box, so its
// constraints fall into up to four cells.
inline BatchScene hubTouching200(unsigned seed) {
    SceneBuilder s("one body touching 200");
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> off(-0.5f, 0.5f);
    const int hub = s.addBody(Vec3{10, 10, 10}, 1);
    for (int i = 0; i < 200; ++i) {
        const Vec3 p{10 + off(rng), 10 + off(rng), 10 + off(rng)};
        const int b = s.addBody(p, 1);
        s.contactAt(hub, b, p);
    }
    // A little pile beside it so that the grid has more than one cell.
    for (int i = 0; i < 20; ++i) {
        const int b = s.addBody(Vec3{float(i), 0, 0.5f}, 1);
        s.groundContact(b);
    }
    return s.take();
}

}  // namespace btocl_test
