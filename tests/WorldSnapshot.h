// A byte-for-byte copy of every collision object and every contact manifold of a world, to show
// that a step which failed changed nothing at all: every field of every body and of every
// manifold point (padding included, so nothing can hide in a field the test forgot).
#pragma once

#include <btBulletDynamicsCommon.h>

#include <cstring>
#include <sstream>
#include <string>
#include <vector>

namespace testworld {

struct WorldSnapshot {
    std::vector<std::vector<unsigned char>> objects, manifolds;
    std::vector<const void*> objectAddresses, manifoldAddresses;

    static WorldSnapshot of(btCollisionWorld& world) {
        WorldSnapshot s;
        const btCollisionObjectArray& all = world.getCollisionObjectArray();
        for (int i = 0; i < all.size(); ++i) {
            const btCollisionObject* o = all[i];
            const size_t size = btRigidBody::upcast(o) ? sizeof(btRigidBody) : sizeof(btCollisionObject);
            s.objects.push_back(bytes(o, size));
            s.objectAddresses.push_back(o);
        }
        btDispatcher* d = world.getDispatcher();
        for (int i = 0; i < d->getNumManifolds(); ++i) {
            const btPersistentManifold* m = d->getManifoldByIndexInternal(i);
            s.manifolds.push_back(bytes(m, sizeof(btPersistentManifold)));
            s.manifoldAddresses.push_back(m);
        }
        return s;
    }

    // "" when `after` holds the same bytes; else the first object or manifold that differs, the
    // byte offset, and for a manifold the contact point it falls in.
    std::string differenceFrom(const WorldSnapshot& after) const {
        std::ostringstream out;
        if (objects.size() != after.objects.size() || manifolds.size() != after.manifolds.size()) {
            out << "counts differ: " << objects.size() << " objects, " << manifolds.size() << " manifolds before; "
                << after.objects.size() << " and " << after.manifolds.size() << " after";
            return out.str();
        }
        for (size_t i = 0; i < objects.size(); ++i) {
            const long at = firstDifference(objects[i], after.objects[i]);
            if (at >= 0) {
                out << "object " << i << " of the world differs at byte " << at << " of " << objects[i].size();
                return out.str();
            }
        }
        for (size_t i = 0; i < manifolds.size(); ++i) {
            const long at = firstDifference(manifolds[i], after.manifolds[i]);
            if (at < 0) continue;
            const auto* m = static_cast<const btPersistentManifold*>(manifoldAddresses[i]);
            const long points = long(reinterpret_cast<const char*>(&m->getContactPoint(0)) -
                                     reinterpret_cast<const char*>(m));
            out << "manifold " << i << " differs at byte " << at;
            if (at >= points && at < points + long(MANIFOLD_CACHE_SIZE * sizeof(btManifoldPoint)))
                out << " (contact point " << (at - points) / long(sizeof(btManifoldPoint)) << ", byte "
                    << (at - points) % long(sizeof(btManifoldPoint)) << " of btManifoldPoint)";
            return out.str();
        }
        return "";
    }

private:
    static std::vector<unsigned char> bytes(const void* p, size_t n) {
        std::vector<unsigned char> out(n);
        std::memcpy(out.data(), p, n);
        return out;
    }
    static long firstDifference(const std::vector<unsigned char>& a, const std::vector<unsigned char>& b) {
        for (size_t k = 0; k < a.size(); ++k)
            if (a[k] != b[k]) return long(k);
        return -1;
    }
};

// What a solve writes to Bullet, as bytes: each body's velocities, transform and companion id,
// each manifold point's impulses, friction directions and flags. Unlike a WorldSnapshot these
// bytes hold no pointers, so two worlds built alike compare equal when they were solved alike.
template <class Bodies, class Manifolds>
std::vector<unsigned char> solveOutputsOf(const Bodies& bodies, const Manifolds& manifolds) {
    std::vector<unsigned char> out;
    auto add = [&out](const void* field, size_t n) {
        const auto* b = static_cast<const unsigned char*>(field);
        out.insert(out.end(), b, b + n);
    };
    for (const btRigidBody* b : bodies) {
        add(&b->getLinearVelocity(), sizeof(btVector3));
        add(&b->getAngularVelocity(), sizeof(btVector3));
        add(&b->getWorldTransform(), sizeof(btTransform));
        const int companion = b->getCompanionId();
        add(&companion, sizeof(int));
    }
    for (const btPersistentManifold* m : manifolds)
        for (int j = 0; j < m->getNumContacts(); ++j) {
            const btManifoldPoint& cp = m->getContactPoint(j);
            add(&cp.m_appliedImpulse, sizeof(btScalar));
            add(&cp.m_appliedImpulseLateral1, sizeof(btScalar));
            add(&cp.m_appliedImpulseLateral2, sizeof(btScalar));
            add(&cp.m_lateralFrictionDir1, sizeof(btVector3));
            add(&cp.m_lateralFrictionDir2, sizeof(btVector3));
            add(&cp.m_contactPointFlags, sizeof(int));
        }
    return out;
}

}  // namespace testworld
