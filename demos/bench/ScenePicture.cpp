#include "ScenePicture.h"

#include "BitmapFont.h"

#include <algorithm>

namespace btbench {

namespace {

// A few distinct, light colours; neighbouring bodies (consecutive indices) differ.
btVector3 bodyColour(size_t index) {
    static const btVector3 palette[] = {
        {0.90f, 0.45f, 0.35f}, {0.95f, 0.75f, 0.30f}, {0.45f, 0.75f, 0.45f},
        {0.40f, 0.60f, 0.90f}, {0.75f, 0.50f, 0.85f}, {0.85f, 0.85f, 0.80f},
    };
    return palette[(index * 7 + index / 6) % (sizeof palette / sizeof palette[0])];
}

std::vector<RenderBox> boxesOf(const btscenes::World& w, bool dynamicOnly) {
    std::vector<RenderBox> boxes;
    const auto& bodies = w.bodies();
    for (size_t i = 0; i < bodies.size(); ++i) {
        const bool dynamic = !bodies[i]->isStaticOrKinematicObject();
        if (dynamicOnly && !dynamic) continue;
        const btVector3 colour = dynamic ? bodyColour(i) : btVector3(0.55f, 0.55f, 0.52f);
        boxes.push_back({bodies[i]->getWorldTransform(), w.halfExtents(i), colour});
    }
    return boxes;
}

// The label in the panel's top-left corner: dark text on a light, mostly opaque strip, at the
// largest scale up to panelHeight / 240 (2 at 480 rows) that fits the panel's width.
void drawLabel(Image& image, int x0, int panelWidth, const std::string& label) {
    if (label.empty()) return;
    int scale = std::max(1, image.height / 240);
    const int margin = 8;
    auto padding = [](int s) { return 3 * s; };
    while (scale > 1 && textWidth(label, scale) + 2 * padding(scale) + 2 * margin > panelWidth) --scale;
    const int pad = padding(scale);
    const int left = x0 + margin, top = margin;
    const int right = std::min(x0 + panelWidth - margin, left + textWidth(label, scale) + 2 * pad);
    const int bottom = std::min(image.height, top + textHeight(scale) + 2 * pad);
    for (int y = top; y < bottom; ++y)
        for (int x = left; x < right; ++x) {
            uint8_t* p = &image.rgb[(size_t(y) * size_t(image.width) + size_t(x)) * 3];
            for (int k = 0; k < 3; ++k) p[k] = uint8_t((int(p[k]) + 6 * 250) / 7);  // 6/7 of near-white
        }
    const uint8_t ink[3] = {25, 25, 30};
    drawText(image, left + pad, top + pad, label, scale, ink, left, right - pad);
}

}  // namespace

Image drawWorlds(const std::vector<Panel>& panels, int panelWidth, int panelHeight) {
    Image image(panelWidth * int(panels.size() > 0 ? panels.size() : 1), panelHeight);
    if (panels.empty()) return image;
    const Camera camera = fitCamera(boxesOf(*panels[0].world, true));
    for (size_t i = 0; i < panels.size(); ++i) {
        renderBoxes(boxesOf(*panels[i].world, false), camera, image, int(i) * panelWidth, panelWidth);
        drawLabel(image, int(i) * panelWidth, panelWidth, panels[i].label);
    }
    // A dark line between panels.
    for (size_t i = 1; i < panels.size(); ++i)
        for (int y = 0; y < panelHeight; ++y)
            for (int x = int(i) * panelWidth - 1; x <= int(i) * panelWidth; ++x)
                for (int k = 0; k < 3; ++k) image.rgb[(size_t(y) * size_t(image.width) + size_t(x)) * 3 + size_t(k)] = 40;
    return image;
}

}  // namespace btbench
