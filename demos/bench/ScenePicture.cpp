#include "ScenePicture.h"

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

}  // namespace

Image drawWorlds(const std::vector<const btscenes::World*>& worlds, int panelWidth, int panelHeight) {
    Image image(panelWidth * int(worlds.size() > 0 ? worlds.size() : 1), panelHeight);
    if (worlds.empty()) return image;
    const Camera camera = fitCamera(boxesOf(*worlds[0], true));
    for (size_t i = 0; i < worlds.size(); ++i)
        renderBoxes(boxesOf(*worlds[i], false), camera, image, int(i) * panelWidth, panelWidth);
    // A dark line between panels.
    for (size_t i = 1; i < worlds.size(); ++i)
        for (int y = 0; y < panelHeight; ++y)
            for (int x = int(i) * panelWidth - 1; x <= int(i) * panelWidth; ++x)
                for (int k = 0; k < 3; ++k) image.rgb[(size_t(y) * size_t(image.width) + size_t(x)) * 3 + size_t(k)] = 40;
    return image;
}

}  // namespace btbench
