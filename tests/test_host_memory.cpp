// The step's host arrays in pinned memory (PinnedHostMemory, as a GPU gets them) against the
// same arrays on the heap: the same elements through growth, copies on the heap, every block
// handed back, and the heap taken where the device has no pinned memory to give; large arrays on
// the heap in huge pages.
#include "HostArray.h"
#include "OclRuntime.h"
#include "PinnedHostMemory.h"

#include <catch2/catch.hpp>

#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
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

namespace {

// The flags of the mapping that holds `address` in /proc/self/smaps ("" where there is none).
std::string mappingFlagsAt(const void* address) {
    std::ifstream smaps("/proc/self/smaps");
    const auto at = reinterpret_cast<std::uintptr_t>(address);
    std::string line;
    bool inside = false;
    while (std::getline(smaps, line)) {
        std::uintptr_t begin = 0, end = 0;
        char dash = 0;
        std::istringstream range(line);
        if (range >> std::hex >> begin >> dash >> end && dash == '-') {
            inside = begin <= at && at < end;
            continue;
        }
        if (inside && line.rfind("VmFlags:", 0) == 0) return line;
    }
    return "";
}

}  // namespace

TEST_CASE("large host arrays on the heap take whole huge pages, small ones stay page-aligned", "[memory]") {
    std::vector<float> want;
    HostArray<float> array;
    bool sawSmall = false, sawLarge = false;
    for (int i = 0; i < 3000000; ++i) {  // 12 MB: grows past kHugeArrayMinBytes
        if (array.size() == array.capacity() && !array.empty()) {
            const auto address = reinterpret_cast<std::uintptr_t>(array.data());
            const bool large = array.capacity() * sizeof(float) >= kHugeArrayMinBytes;
            CHECK(address % (large ? kHugePageBytes : kHostArrayAlignment) == 0);
            sawSmall = sawSmall || !large;
            sawLarge = sawLarge || large;
        }
        array.push_back(float(i) * 0.5f);
        want.push_back(float(i) * 0.5f);
    }
    CHECK(sawSmall);
    CHECK(sawLarge);
    CHECK(std::vector<float>(array.begin(), array.end()) == want);
    CHECK(reinterpret_cast<std::uintptr_t>(array.data()) % kHugePageBytes == 0);
#ifdef __linux__
    // Advised as huge (VmFlags "hg") where the kernel has transparent huge pages: whether it
    // backs them so is its choice.
    if (std::ifstream("/sys/kernel/mm/transparent_hugepage/enabled")) {
        const std::string flags = mappingFlagsAt(array.data() + array.size() / 2);
        INFO(flags);
        CHECK(flags.find(" hg") != std::string::npos);
    }
#endif
    // A small array made from a part of it takes page-aligned memory, not huge pages.
    HostArray<float> small(array.begin(), array.begin() + 1000);
    CHECK(reinterpret_cast<std::uintptr_t>(small.data()) % kHostArrayAlignment == 0);
    CHECK(std::vector<float>(small.begin(), small.end()) == std::vector<float>(want.begin(), want.begin() + 1000));
}
