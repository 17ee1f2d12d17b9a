// The step's host arrays in pinned memory (PinnedHostMemory, as a GPU gets them) against the
// same arrays on the heap: the same elements through growth, copies on the heap, every block
// handed back, and the heap taken where the device has no pinned memory to give.
#include "HostArray.h"
#include "OclRuntime.h"
#include "PinnedHostMemory.h"

#include <catch2/catch.hpp>

#include <cstdint>
#include <vector>

using namespace btocl;

TEST_CASE("host arrays in pinned memory keep their elements as they grow, and give it all back", "[memory]") {
    OclRuntime rt("");
    PinnedHostMemory pinned(rt);
    std::vector<int> want;
    {
        HostArray<int> array{HostArrayAllocator<int>(&pinned)};
        for (int i = 0; i < 100000; ++i) {  // grows through about 17 blocks, each one moved
            array.push_back(i * 7);
            want.push_back(i * 7);
        }
        CHECK(std::vector<int>(array.begin(), array.end()) == want);
        CHECK(reinterpret_cast<std::uintptr_t>(array.data()) % kHostArrayAlignment == 0);
        CHECK(pinned.bytesHeld() == array.capacity() * sizeof(int));  // the old blocks went back

        // A copy takes the heap: it may outlive the pinned memory.
        const HostArray<int> copy = array;
        CHECK(copy.get_allocator().source == nullptr);
        CHECK(pinned.bytesHeld() == array.capacity() * sizeof(int));
        CHECK(std::vector<int>(copy.begin(), copy.end()) == want);

        // Moved to the heap and back, the elements stay.
        moveToSource(array, nullptr);
        CHECK(pinned.bytesHeld() == 0);
        moveToSource(array, &pinned);
        CHECK(pinned.bytesHeld() >= want.size() * sizeof(int));
        CHECK(std::vector<int>(array.begin(), array.end()) == want);
    }
    CHECK(pinned.bytesHeld() == 0);
}

TEST_CASE("pinned memory past what the device can allocate falls back to the heap", "[memory]") {
    OclRuntime rt("");
    PinnedHostMemory pinned(rt);
    CHECK(pinned.allocate(rt.maxAllocSize()) == nullptr);  // a page more than the device's limit
    CHECK(pinned.allocate(0) == nullptr);
    int onHeap = 0;
    CHECK_FALSE(pinned.deallocate(&onHeap));  // not its own: the array frees it as heap memory
    void* p = pinned.allocate(1000);
    REQUIRE(p != nullptr);
    CHECK(pinned.bytesHeld() == 1000);
    CHECK(pinned.deallocate(p));
    CHECK(pinned.bytesHeld() == 0);
}
