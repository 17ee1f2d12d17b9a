#include "Raster.h"

#include <algorithm>
#include <cmath>

namespace btbench {

Image::Image(int w, int h) : width(w), height(h), rgb(size_t(w) * size_t(h) * 3, 0) {}

Camera fitCamera(const std::vector<RenderBox>& boxes) {
    btVector3 lo(BT_LARGE_FLOAT, BT_LARGE_FLOAT, BT_LARGE_FLOAT), hi = -lo;
    for (const RenderBox& b : boxes) {
        const btScalar r = b.halfExtents.length();
        lo.setMin(b.transform.getOrigin() - btVector3(r, r, r));
        hi.setMax(b.transform.getOrigin() + btVector3(r, r, r));
    }
    Camera c;
    if (boxes.empty()) { c.eye = btVector3(10, 10, 10); c.target = btVector3(0, 0, 0); return c; }
    c.target = 0.5f * (lo + hi);
    const btScalar radius = std::max(btScalar(1), 0.5f * (hi - lo).length());
    const btScalar distance = radius / std::sin(0.5f * c.fovYDegrees * SIMD_RADS_PER_DEG) * 1.05f;
    c.eye = c.target + btVector3(0.55f, 0.45f, 1.0f).normalized() * distance;
    return c;
}

namespace {

const btScalar kNear = 0.05f;

// Clips a convex polygon (camera space) to z <= -kNear, the part in front of the camera.
std::vector<btVector3> clipNear(const std::vector<btVector3>& poly) {
    std::vector<btVector3> out;
    for (size_t i = 0; i < poly.size(); ++i) {
        const btVector3& a = poly[i];
        const btVector3& b = poly[(i + 1) % poly.size()];
        const bool aIn = a.z() <= -kNear, bIn = b.z() <= -kNear;
        if (aIn) out.push_back(a);
        if (aIn != bIn) {
            const btScalar t = (-kNear - a.z()) / (b.z() - a.z());
            out.push_back(a + (b - a) * t);
        }
    }
    return out;
}

struct Rasteriser {
    Image& image;
    std::vector<float>& depth;  // 1 / distance along the view axis; larger is nearer
    int x0, width;
    btScalar focal;              // pixels per unit at distance 1

    void triangle(const btVector3 s[3], const uint8_t rgb[3]) {
        // s: screen x, y and 1/z (linear in screen space under perspective).
        const btScalar area = (s[1].x() - s[0].x()) * (s[2].y() - s[0].y()) - (s[2].x() - s[0].x()) * (s[1].y() - s[0].y());
        if (std::fabs(area) < 1e-12f) return;
        const int minX = std::max(x0, int(std::floor(std::min({s[0].x(), s[1].x(), s[2].x()}))));
        const int maxX = std::min(x0 + width - 1, int(std::ceil(std::max({s[0].x(), s[1].x(), s[2].x()}))));
        const int minY = std::max(0, int(std::floor(std::min({s[0].y(), s[1].y(), s[2].y()}))));
        const int maxY = std::min(image.height - 1, int(std::ceil(std::max({s[0].y(), s[1].y(), s[2].y()}))));
        for (int y = minY; y <= maxY; ++y)
            for (int x = minX; x <= maxX; ++x) {
                const btScalar px = btScalar(x) + 0.5f, py = btScalar(y) + 0.5f;
                const btScalar w0 = ((s[1].x() - px) * (s[2].y() - py) - (s[2].x() - px) * (s[1].y() - py)) / area;
                const btScalar w1 = ((s[2].x() - px) * (s[0].y() - py) - (s[0].x() - px) * (s[2].y() - py)) / area;
                const btScalar w2 = 1 - w0 - w1;
                if (w0 < 0 || w1 < 0 || w2 < 0) continue;
                const float invZ = float(w0 * s[0].z() + w1 * s[1].z() + w2 * s[2].z());
                float& d = depth[size_t(y) * size_t(image.width) + size_t(x)];
                if (invZ <= d) continue;
                d = invZ;
                uint8_t* out = &image.rgb[(size_t(y) * size_t(image.width) + size_t(x)) * 3];
                out[0] = rgb[0]; out[1] = rgb[1]; out[2] = rgb[2];
            }
    }

    void polygon(const std::vector<btVector3>& view, const uint8_t rgb[3]) {
        const std::vector<btVector3> poly = clipNear(view);
        if (poly.size() < 3) return;
        std::vector<btVector3> screen;
        for (const btVector3& v : poly) {
            const btScalar invZ = 1 / -v.z();
            screen.emplace_back(btScalar(x0) + 0.5f * btScalar(width) + v.x() * focal * invZ,
                                0.5f * btScalar(image.height) - v.y() * focal * invZ, invZ);
        }
        for (size_t i = 1; i + 1 < screen.size(); ++i) {
            const btVector3 tri[3] = {screen[0], screen[i], screen[i + 1]};
            triangle(tri, rgb);
        }
    }
};

}  // namespace

void renderBoxes(const std::vector<RenderBox>& boxes, const Camera& camera, Image& image, int x0, int width) {
    // Sky: a vertical gradient.
    for (int y = 0; y < image.height; ++y)
        for (int x = x0; x < x0 + width; ++x) {
            uint8_t* p = &image.rgb[(size_t(y) * size_t(image.width) + size_t(x)) * 3];
            const float t = float(y) / float(image.height);
            p[0] = uint8_t(170 + 60 * t); p[1] = uint8_t(195 + 45 * t); p[2] = uint8_t(235 + 15 * t);
        }
    std::vector<float> depth(size_t(image.width) * size_t(image.height), 0.0f);  // 0 = infinitely far

    // Camera space: x right, y up, looking down -z.
    const btVector3 forward = (camera.target - camera.eye).normalized();
    const btVector3 right = forward.cross(camera.up).normalized();
    const btVector3 up = right.cross(forward);
    const btScalar focal = 0.5f * btScalar(image.height) / std::tan(0.5f * camera.fovYDegrees * SIMD_RADS_PER_DEG);
    Rasteriser r{image, depth, x0, width, focal};
    const btVector3 light = btVector3(0.4f, 1.0f, 0.6f).normalized();

    // Each face: the axis it faces along and its sign; corners walk the face in order.
    static const int kCorner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (const RenderBox& box : boxes) {
        const btMatrix3x3& basis = box.transform.getBasis();
        for (int axis = 0; axis < 3; ++axis)
            for (int sign = -1; sign <= 1; sign += 2) {
                const btVector3 normal = basis.getColumn(axis) * btScalar(sign);
                const btVector3 faceCentre = box.transform.getOrigin() + normal * box.halfExtents[axis];
                if (normal.dot(camera.eye - faceCentre) <= 0) continue;  // back face
                const int u = (axis + 1) % 3, v = (axis + 2) % 3;
                std::vector<btVector3> view;
                for (const auto& c : kCorner) {
                    btVector3 local(0, 0, 0);
                    local[axis] = btScalar(sign) * box.halfExtents[axis];
                    local[u] = btScalar(c[0]) * box.halfExtents[u];
                    local[v] = btScalar(c[1]) * box.halfExtents[v];
                    const btVector3 d = box.transform(local) - camera.eye;
                    view.emplace_back(d.dot(right), d.dot(up), -d.dot(forward));
                }
                const btScalar shade = 0.35f + 0.65f * std::max(btScalar(0), normal.dot(light));
                uint8_t rgb[3];
                for (int k = 0; k < 3; ++k) rgb[k] = uint8_t(std::min(btScalar(255), 255 * box.colour[k] * shade));
                r.polygon(view, rgb);
            }
    }
}

}  // namespace btbench
