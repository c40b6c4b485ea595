// huge_pages.h (internal): the engine's arrays give back the pages they no longer use while they
// keep their room, and say when a shrinking use is worth a release.
#include "huge_pages.h"

#include <gtest/gtest.h>

#include <cstdint>

namespace ddsimp::detail {
namespace {

constexpr size_t kPage = 4096;
constexpr size_t kPerPage = kPage / sizeof(uint32_t);

// The value at index i of the array's room, read through its storage (past its size too).
uint32_t stored_at(const Array<uint32_t>& array, size_t i) {
    return static_cast<const volatile uint32_t*>(array.data())[i];
}

// The index of the first element of the first whole page at or after index i, and the end of
// the last whole page of the array's room (an allocation need not start or end on a page).
size_t whole_pages_from(const Array<uint32_t>& array, size_t i) {
    const uintptr_t at = reinterpret_cast<uintptr_t>(array.data() + i);
    return i + ((kPage - at % kPage) % kPage) / sizeof(uint32_t);
}
size_t whole_pages_end(const Array<uint32_t>& array) {
    const uintptr_t end = reinterpret_cast<uintptr_t>(array.data() + array.capacity());
    return array.capacity() - (end % kPage) / sizeof(uint32_t);
}

TEST(HugePages, ReleaseUnusedKeepsTheContentsAndGivesBackThePagesPastTheEnd) {
    Array<uint32_t> array(1024 * kPerPage, 7); // 4 MiB: in huge pages where the system has them
    const size_t kept = 3 * kPerPage + 100;
    array.resize(kept);
    release_unused(array);
    ASSERT_EQ(array.capacity(), 1024 * kPerPage);
    for (size_t i = 0; i < kept; ++i) ASSERT_EQ(array[i], 7u) << i;
    // Every whole page past the end was given back: the system gives zeros when it is read.
    for (size_t i = whole_pages_from(array, kept); i < whole_pages_end(array); i += kPerPage / 4)
        ASSERT_EQ(stored_at(array, i), 0u) << i;
    // It grows again in place.
    const uint32_t* before = array.data();
    array.resize(array.capacity(), 3);
    EXPECT_EQ(array.data(), before);
    EXPECT_EQ(array[kept - 1], 7u);
    EXPECT_EQ(array[kept], 3u);
    EXPECT_EQ(array.back(), 3u);
}

TEST(HugePages, ClearAndReleaseEmptiesAndKeepsTheRoom) {
    Array<uint32_t> array(64 * kPerPage, 5); // 256 KiB: in small pages
    clear_and_release(array);
    EXPECT_TRUE(array.empty());
    EXPECT_EQ(array.capacity(), 64 * kPerPage);
    for (size_t i = whole_pages_from(array, 0); i < whole_pages_end(array); i += kPerPage / 4)
        ASSERT_EQ(stored_at(array, i), 0u) << i;
    array.assign(10, 9);
    EXPECT_EQ(array.size(), 10u);
    EXPECT_EQ(array[9], 9u);
}

TEST(HugePages, HalvingReleaseIsDueOnceTheUseIsBelowHalfTheLastRelease) {
    HalvingRelease release;
    EXPECT_TRUE(release.due(100)); // the first use
    EXPECT_FALSE(release.due(100));
    EXPECT_FALSE(release.due(51));
    EXPECT_FALSE(release.due(50)); // half: not below it
    EXPECT_TRUE(release.due(49));
    EXPECT_FALSE(release.due(90)); // measured from the last release, 49
    EXPECT_FALSE(release.due(25));
    EXPECT_TRUE(release.due(24));
    EXPECT_TRUE(release.due(0));
    EXPECT_FALSE(release.due(0));
}

} // namespace
} // namespace ddsimp::detail
