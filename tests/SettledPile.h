// A pile settled by Bullet's solver, and a solver of ours driven by hand on all of the world's
// objects and manifolds, as btDiscreteDynamicsWorld drives it (prepareSolve, one solveGroup,
// allSolved) but with nothing else in between: no collision detection, no integration. So a
// solve that fails can be compared with the world byte for byte (WorldSnapshot.h), and two
// piles built alike stay bitwise alike.
#pragma once

#include "Scenes.h"

#include <functional>
#include <vector>

namespace testworld {

struct SettledPile {
    World w{SolverKind::Reference};
    btConstraintSolver& solver;
    std::vector<btCollisionObject*> objects;
    std::vector<btPersistentManifold*> manifolds;
    btRigidBody* top = nullptr;  // a box of the upper layer, resting on boxes below it

    // 20 boxes (16 on the ground, 4 on top of them); `prepare` may change the world (bodies,
    // solver settings) before it settles, in 60 steps of SI.
    explicit SettledPile(btConstraintSolver& s, const std::function<void(World&)>& prepare = nullptr) : solver(s) {
        groundAndPile(w, 20);
        if (prepare) prepare(w);
        for (int i = 0; i < 60; ++i) w.step();
        const btCollisionObjectArray& all = w.dyn().getCollisionObjectArray();
        for (int i = 0; i < all.size(); ++i) objects.push_back(all[i]);
        manifolds = w.manifolds();
        top = w.body(17);
    }
    btContactSolverInfo info() const { return w.stepInfo(); }
    void solve() { solve(info()); }
    void solve(const btContactSolverInfo& i) {
        solver.prepareSolve(int(objects.size()), int(manifolds.size()));
        solver.solveGroup(objects.data(), int(objects.size()), manifolds.data(), int(manifolds.size()), nullptr, 0, i,
                          nullptr, &w.dispatcher());
        solver.allSolved(i, nullptr);
    }
    // A manifold between `top` and a dynamic box below it.
    btPersistentManifold* manifoldOfTop() const {
        for (btPersistentManifold* m : manifolds) {
            const btCollisionObject* other = m->getBody0() == top ? m->getBody1() : m->getBody0();
            if ((m->getBody0() == top || m->getBody1() == top) && !other->isStaticObject() && m->getNumContacts() > 0)
                return m;
        }
        return nullptr;
    }
    // The last manifold with points, in the order the solver gets them.
    btPersistentManifold* lastManifold() const {
        for (auto it = manifolds.rbegin(); it != manifolds.rend(); ++it)
            if ((*it)->getNumContacts() > 0) return *it;
        return nullptr;
    }
};

}  // namespace testworld
