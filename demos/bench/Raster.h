// A small software rasteriser for pictures of a scene: boxes drawn in perspective with a
// z-buffer and flat shading per face (no OpenGL, runs headless).
#pragma once

#include <LinearMath/btTransform.h>

#include <cstdint>
#include <vector>

namespace btbench {

struct RenderBox {
    btTransform transform;
    btVector3 halfExtents;
    btVector3 colour;  // RGB in [0, 1]
};

struct Camera {
    btVector3 eye, target, up{0, 1, 0};
    btScalar fovYDegrees = 50;
};

// Looks at the boxes' bounding sphere from above and to the side, so all of it is in view.
Camera fitCamera(const std::vector<RenderBox>& boxes);

struct Image {
    int width = 0, height = 0;
    std::vector<uint8_t> rgb;  // row-major, top row first, 3 bytes per pixel
    Image(int w, int h);
};

// Draws the boxes into image columns [x0, x0 + width) (so two panels can share one image).
void renderBoxes(const std::vector<RenderBox>& boxes, const Camera& camera, Image& image, int x0, int width);

}  // namespace btbench
