// Parity with btSequentialImpulseConstraintSolver at rest (issue #13): scenes that start at rest
// -- a pyramid, a brick wall and a small dense block -- stepped 10 s in the same process by SI
// and by ours; our largest drift and resting kinetic energy are at most 1.3x SI's plus a small
// floor, and the same stacks stand. With sleeping allowed, a pyramid's bodies fall asleep within
// 10% of the step at which SI's do.
//
// The kinetic energy compared is the mean over the last 150 of the 600 steps, not the last
// state's: at rest it is a jitter that swings from step to step, so one sample says little.
// SI's own on the dense block: 5.8e-5 J in the last state, 4.1e-4 J the mean of the window.
#include "Scenes.h"

#include <algorithm>
#include <cstdio>
#include <functional>
#include <string>
#include <utility>
#include <vector>

using namespace testworld;

namespace {

// Sum over dynamic bodies of 1/2 m v^2 + 1/2 w . I w (the inertia is diagonal in the body frame).
double kineticEnergy(const World& w) {
    double energy = 0;
    for (const btRigidBody* b : w.bodies()) {
        if (b->isStaticOrKinematicObject()) continue;
        const btVector3 v = b->getLinearVelocity();
        const btVector3 local = b->getAngularVelocity() * b->getWorldTransform().getBasis();  // R^T w
        const btVector3 invI = b->getInvInertiaDiagLocal();
        double rot = 0;
        for (int k = 0; k < 3; ++k)
            if (invI[k] > 0) rot += double(local[k]) * double(local[k]) / double(invI[k]);
        energy += 0.5 * double(v.length2()) / double(b->getInvMass()) + 0.5 * rot;
    }
    return energy;
}

// A stack stands when no box has dropped or tipped, as in test_parity_stacks.cpp: every box
// within 5 cm of its start height and its up axis within 10 degrees of vertical. Sideways creep
// is no criterion (SI's own depends chaotically on its order); drift measures it.
bool stands(const World& w, const std::vector<btVector3>& start) {
    for (size_t i = 0; i < w.bodies().size(); ++i) {
        const btRigidBody* b = w.body(i);
        if (b->isStaticOrKinematicObject()) continue;
        const btVector3 up = b->getWorldTransform().getBasis().getColumn(1);
        if (std::fabs(pos(b).y() - start[i].y()) > 0.05 || up.y() < std::cos(10 * SIMD_RADS_PER_DEG)) return false;
    }
    return true;
}

// The ground and a small dense block: layers of 4 x 4 unit boxes face to face, 4 high (64 boxes,
// about 900 contact points: each box touches up to six neighbours).
void groundAndDenseBlock(World& w) {
    w.addGround();
    for (int layer = 0; layer < 4; ++layer)
        for (int iz = 0; iz < 4; ++iz)
            for (int ix = 0; ix < 4; ++ix)
                w.addUnitBox(btVector3(btScalar(ix) - 1.5f, 0.5f + btScalar(layer), btScalar(iz) - 1.5f), stackedBox());
}

struct RestingFigures {
    double maxDrift = 0;       // largest distance of a box from where it started, over the run
    double restingEnergy = 0;  // mean kinetic energy over the resting window
    double finalEnergy = 0;    // kinetic energy of the last state
    bool stands = false;
};

constexpr int kSteps = 600;          // 10 s
constexpr int kRestingWindow = 150;  // the last quarter, as btocl_bench's restingKineticEnergy

// Measures one world of a lock-step run: call after() after every step, finish() at the end.
class RestingTracker {
public:
    explicit RestingTracker(const World& w) : m_start(positionsOf(w)) {}
    void after(const World& w) {
        ++m_step;
        m_figures.maxDrift = std::max(m_figures.maxDrift, double(maxDisplacement(w, m_start)));
        if (m_step > kSteps - kRestingWindow) m_figures.restingEnergy += kineticEnergy(w) / kRestingWindow;
    }
    RestingFigures finish(const World& w) {
        m_figures.finalEnergy = kineticEnergy(w);
        m_figures.stands = stands(w, m_start);
        return m_figures;
    }

private:
    std::vector<btVector3> m_start;
    RestingFigures m_figures;
    int m_step = 0;
};

// Builds the scene in both worlds and steps them kSteps in lock step: the reference's figures
// and the candidate's.
std::pair<RestingFigures, RestingFigures> runResting(World& ref, World& candidate,
                                                     const std::function<void(World&)>& scene,
                                                     const std::function<void(World&)>& candidateScene = {}) {
    ref.info().m_numIterations = candidate.info().m_numIterations = 10;
    scene(ref);
    (candidateScene ? candidateScene : scene)(candidate);
    RestingTracker trackRef(ref), trackCandidate(candidate);
    for (int i = 0; i < kSteps; ++i) {
        ref.step();
        candidate.step();
        trackRef.after(ref);
        trackCandidate.after(candidate);
    }
    return {trackRef.finish(ref), trackCandidate.finish(candidate)};
}

void printFigures(const char* label, const RestingFigures& ref, const RestingFigures& other) {
    std::printf("%s: drift %.5f %.5f restKE %.4g %.4g finalKE %.4g %.4g stands %d %d\n", label, ref.maxDrift,
                other.maxDrift, ref.restingEnergy, other.restingEnergy, ref.finalEnergy, other.finalEnergy, ref.stands,
                other.stands);
}

// The floors, from SI against itself in other orders (the hidden test below: SI with
// SOLVER_RANDMIZE_ORDER, seeds 0 to 7, against SI in its fixed order, 10 s at 10 iterations):
// - drift: SI's shuffled drift is below its fixed one on all three scenes (pyramid 7.5-7.7 mm
//   against 22.8 mm, wall 10-12 mm against 42 mm, block 4.7-7.2 mm against 15 mm), so the spread
//   asks for no floor; 2 mm covers the jitter of a resting box about its place (about 1 mm,
//   TestWorld.h's worstExcessGap), which a bound near a small drift must allow either way.
// - resting kinetic energy: SI in a shuffled order rests at a higher jitter than in its fixed
//   one on the pyramid (2.53e-4 to 2.69e-4 J against 4.30e-5 J, 55 boxes) and the wall (3.86e-4
//   to 4.35e-4 J against 1.65e-4 J, 44 bricks): up to 2.13e-4 and 2.21e-4 J above 1.3x the fixed
//   order's, 3.9e-6 and 5.0e-6 J a body. 5e-6 J a body of 1 kg (a speed of 3.2 mm/s) covers
//   that: the bounds hold for SI against itself in any of these orders.
constexpr double kDriftFloor = 0.002;                // m
constexpr double kRestingEnergyFloorPerBody = 5e-6;  // J, bodies of 1 kg

int numDynamicBodies(const World& w) {
    int n = 0;
    for (const btRigidBody* b : w.bodies()) n += b->isStaticOrKinematicObject() ? 0 : 1;
    return n;
}

// The scene with every dynamic body moved by `shift` along x (and half of it along z).
std::function<void(World&)> shifted(const std::function<void(World&)>& scene, btScalar shift) {
    return [scene, shift](World& w) {
        scene(w);
        for (btRigidBody* body : w.bodies())
            if (!body->isStaticOrKinematicObject()) body->translate(btVector3(shift, 0, shift * btScalar(0.5)));
    };
}

// SI's figures are taken as the worst of three runs, the scene as built and moved by 2 and 4 um:
// at rest the jitter is chaotic, and ours in SI's order differs from SI by float rounding alone.
// SI against itself moved by 1 to 6 um (hidden test "[perturbed]"): pyramid 3.7e-5 to 4.3e-5 J,
// wall 1.5e-4 to 3.5e-4 J, dense block 2.2e-4 to 1.14e-3 J (4.1e-4 J unmoved) and drift 14 to
// 23 mm (15 mm unmoved).
void requireRestsAsSI(const std::function<void(World&)>& scene) {
    Pair p;
    auto [ref, ours] = runResting(p.ref, p.ours, scene);
    World a(SolverKind::Reference), b(SolverKind::Reference);
    const auto [moved2, moved4] = runResting(a, b, shifted(scene, btScalar(2e-6)), shifted(scene, btScalar(4e-6)));
    for (const RestingFigures& moved : {moved2, moved4}) {
        ref.maxDrift = std::max(ref.maxDrift, moved.maxDrift);
        ref.restingEnergy = std::max(ref.restingEnergy, moved.restingEnergy);
        ref.stands = ref.stands && moved.stands;
    }
    const double driftBound = 1.3 * ref.maxDrift + kDriftFloor;
    const double energyBound = 1.3 * ref.restingEnergy + kRestingEnergyFloorPerBody * numDynamicBodies(p.ref);
    CAPTURE(ref.maxDrift, ours.maxDrift, driftBound);
    CAPTURE(ref.restingEnergy, ours.restingEnergy, energyBound, ref.finalEnergy, ours.finalEnergy);
    CAPTURE(ref.stands, ours.stands);
    CHECK(ref.stands);
    CHECK(ours.stands == ref.stands);
    CHECK(ours.maxDrift <= driftBound);
    CHECK(ours.restingEnergy <= energyBound);
}

// True when every dynamic body of the world sleeps (its island deactivated).
bool allAsleep(const World& w) {
    for (const btRigidBody* b : w.bodies())
        if (!b->isStaticOrKinematicObject() && b->getActivationState() != ISLAND_SLEEPING) return false;
    return true;
}

double maxSpeed(const World& w) {
    double v = 0;
    for (const btRigidBody* b : w.bodies()) v = std::max(v, double(b->getLinearVelocity().length()));
    return v;
}

// SI whose SOLVER_RANDMIZE_ORDER (set in the world's solver info) starts from `seed`.
std::unique_ptr<btConstraintSolver> shuffledSI(unsigned long seed) {
    auto si = std::make_unique<btSequentialImpulseConstraintSolver>();
    si->setRandSeed(seed);
    return si;
}

// Bullet deactivates a body that has stayed below its sleeping thresholds (0.8 m/s, 1 rad/s)
// for gDeactivationTime (2 s), an island once all its bodies want to. The step at which every
// body of the pyramid sleeps, in each world.
struct SleepFigures {
    int asleepRef = -1, asleepOurs = -1;        // the first step after which every body sleeps
    double maxSpeedRef = 0, maxSpeedOurs = 0;  // the fastest body while awake
};

SleepFigures stepsToSleep(const std::function<void(World&)>& scene) {
    Pair p;
    p.ref.allowSleeping();
    p.ours.allowSleeping();
    p.configure([](btContactSolverInfo& i) { i.m_numIterations = 10; });
    p.build(scene);
    SleepFigures f;
    for (int step = 1; step <= 1200 && (f.asleepRef < 0 || f.asleepOurs < 0); ++step) {  // 20 s at most
        p.step();
        if (f.asleepRef < 0) f.maxSpeedRef = std::max(f.maxSpeedRef, maxSpeed(p.ref));
        if (f.asleepOurs < 0) f.maxSpeedOurs = std::max(f.maxSpeedOurs, maxSpeed(p.ours));
        if (f.asleepRef < 0 && allAsleep(p.ref)) f.asleepRef = step;
        if (f.asleepOurs < 0 && allAsleep(p.ours)) f.asleepOurs = step;
    }
    return f;
}

}  // namespace

TEST_CASE("parity: a pyramid with a base of 10 rests as with SI", "[parity][resting]") {
    requireRestsAsSI([](World& w) { groundAndPyramid(w, 10); });
}

TEST_CASE("parity: a brick wall rests as with SI", "[parity][resting]") {
    requireRestsAsSI([](World& w) { groundAndBrickWall(w, 8); });
}

TEST_CASE("parity: a small dense block rests as with SI", "[parity][resting]") {
    requireRestsAsSI([](World& w) { groundAndDenseBlock(w); });
}

// rotatePoints goes past SI (issue #13, item 4): each velocity iteration starts a manifold's
// points at another one, so that no point always takes the largest share. Measured (btocl_bench,
// 600 steps, pyramid with a base of 20): drift 0.046 m against SI's 0.259, resting kinetic
// energy 4.2e-4 J against 2.3e-2 J. Bounds: half of SI's figures, on two scenes.
TEST_CASE("rotatePoints: a pyramid and a wall rest with less drift and energy than with SI", "[parity][resting]") {
    btOpenCLSolverConfig rotated = validatingConfig();
    rotated.rotatePoints = true;
    for (const auto& [name, scene] : std::vector<std::pair<std::string, std::function<void(World&)>>>{
             {"pyramid 20", [](World& w) { groundAndPyramid(w, 20); }},
             {"wall 10", [](World& w) { groundAndBrickWall(w, 10); }}}) {
        INFO(name);
        World ref(SolverKind::Reference), ours(SolverKind::OpenCL, rotated);
        auto [si, figures] = runResting(ref, ours, scene);
        printFigures(name.c_str(), si, figures);
        CAPTURE(si.maxDrift, figures.maxDrift, si.restingEnergy, figures.restingEnergy);
        CHECK(figures.maxDrift <= 0.5 * si.maxDrift);
        CHECK(figures.restingEnergy <= 0.5 * si.restingEnergy);
        CHECK(figures.stands);
    }
}

// SOLVER_RANDMIZE_ORDER is honoured (kernels/row_solve.h: our velocity passes walk shuffled
// orders; SI shuffles its rows): what it is for, resting stacks that creep several times less
// than in the fixed order, holds for ours as for SI. Bounds: at most half of SI's drift in its
// fixed order (as rotatePoints above), and SI's randomized order's resting energy as
// requireRestsAsSI bounds SI's: 1.3x plus the floor, SI's figure the worst of four of its seeds
// (its shuffled jitter is chaotic too). Measured (serial path; wide): pyramid drift 7.7 mm (9.9)
// against SI's 21 mm fixed and 7.6 mm randomized, energy 6.7e-5 J (1.4e-4) against 2.7e-4 J;
// wall 15 mm (18) against 42 mm and 12 mm, energy 6.8e-4 J (6.0e-4) against 4.2e-4 J.
TEST_CASE("SOLVER_RANDMIZE_ORDER: a pyramid and a wall creep less than in the fixed order, as with SI's",
          "[parity][resting]") {
    for (const auto& [name, scene] : std::vector<std::pair<std::string, std::function<void(World&)>>>{
             {"pyramid 10", [](World& w) { groundAndPyramid(w, 10); }},
             {"wall 8", [](World& w) { groundAndBrickWall(w, 8); }}}) {
        INFO(name);
        World fixedSI(SolverKind::Reference), candidate(SolverKind::OpenCL);
        candidate.info().m_solverMode |= SOLVER_RANDMIZE_ORDER;
        const auto [fixed, ours] = runResting(fixedSI, candidate, scene);
        printFigures(name.c_str(), fixed, ours);
        double shuffledEnergy = 0;  // SI's randomized order, the worst of seeds 0 to 3
        for (unsigned long seed = 0; seed < 4; seed += 2) {
            World a(shuffledSI(seed)), b(shuffledSI(seed + 1));
            for (World* w : {&a, &b}) w->info().m_solverMode |= SOLVER_RANDMIZE_ORDER;
            const auto [first, second] = runResting(a, b, scene);
            shuffledEnergy = std::max({shuffledEnergy, first.restingEnergy, second.restingEnergy});
        }
        const double energyBound = 1.3 * shuffledEnergy + kRestingEnergyFloorPerBody * numDynamicBodies(candidate);
        CAPTURE(fixed.maxDrift, ours.maxDrift, shuffledEnergy, ours.restingEnergy, energyBound);
        CHECK(ours.stands);
        CHECK(ours.maxDrift <= 0.5 * fixed.maxDrift);
        CHECK(ours.restingEnergy <= energyBound);
    }
}

// A pyramid that starts at rest sleeps a little after step 120 (2 s) in both worlds, unless a
// solver shakes it above the thresholds. One dropped from 1 m lands, settles and then sleeps:
// the step says when each solver brought it to rest. Measured (SI, ours serial, ours wide): at
// rest 122, 122, 122; dropped 184, 188, 195. With thresholds 8x to 40x tighter (serial path) the
// two still sleep within 4% of each other, bar the dropped pyramid at 0.02 m/s (SI 240, ours
// 205, SI in a shuffled order 215).
TEST_CASE("parity: with sleeping allowed a pyramid falls asleep when SI's does", "[parity][resting][sleeping]") {
    const btScalar lift = GENERATE(btScalar(0), btScalar(1));
    CAPTURE(lift);
    const SleepFigures f = stepsToSleep([lift](World& w) {
        w.addGround();
        for (int row = 0; row < 10; ++row)
            for (int i = 0; i < 10 - row; ++i)
                w.addUnitBox(btVector3(btScalar(i) + 0.5f * btScalar(row) - 4.5f, 0.5f + lift + btScalar(row), 0),
                             stackedBox());
    });
    CAPTURE(f.asleepRef, f.asleepOurs, f.maxSpeedRef, f.maxSpeedOurs);
    REQUIRE(f.asleepRef > 0);
    REQUIRE(f.asleepOurs > 0);
    CHECK(std::abs(f.asleepOurs - f.asleepRef) <= 0.1 * f.asleepRef);
}

// Where the floors come from: SI against itself in other Gauss-Seidel orders (its randomized
// mode, several seeds). Hidden: run it with `btocl_tests "[floors]"`.
TEST_CASE("resting floors: SI against SI in shuffled orders", "[.][floors]") {
    const std::pair<const char*, std::function<void(World&)>> scenes[] = {
        {"pyramid", [](World& w) { groundAndPyramid(w, 10); }},
        {"wall", [](World& w) { groundAndBrickWall(w, 8); }},
        {"block", [](World& w) { groundAndDenseBlock(w); }}};
    for (const auto& [name, scene] : scenes)
        for (unsigned long seed = 0; seed < 8; ++seed) {
            World ref(SolverKind::Reference), shuffled(shuffledSI(seed));
            shuffled.info().m_solverMode |= SOLVER_RANDMIZE_ORDER;
            const auto [a, b] = runResting(ref, shuffled, scene);
            char label[64];
            std::snprintf(label, sizeof label, "%s seed %lu", name, seed);
            printFigures(label, a, b);
        }
}

// SI against itself started a few micrometres apart: at rest, how far does its own jitter wander
// from float-level differences (ours in SI's order differs from SI by rounding alone)? Hidden:
// `btocl_tests "[perturbed]"`.
TEST_CASE("resting floors: SI against SI started a few micrometres apart", "[.][perturbed]") {
    const std::pair<const char*, std::function<void(World&)>> scenes[] = {
        {"pyramid", [](World& w) { groundAndPyramid(w, 10); }},
        {"wall", [](World& w) { groundAndBrickWall(w, 8); }},
        {"block", [](World& w) { groundAndDenseBlock(w); }}};
    for (const auto& [name, scene] : scenes)
        for (int k = 1; k <= 6; ++k) {
            World ref(SolverKind::Reference), moved(SolverKind::Reference);
            const auto [a, b] = runResting(ref, moved, scene, shifted(scene, btScalar(k) * btScalar(1e-6)));
            char label[64];
            std::snprintf(label, sizeof label, "%s moved %d um", name, k);
            printFigures(label, a, b);
        }
}
