// CoilIdFilter: no false negatives (through growth and chosen slot
// collisions), a negligible false-positive rate, the load factor bound.
#include "storage/coil_id_filter.h"

#include <bit>
#include <string>

#include <gtest/gtest.h>

namespace rollwear::storage::internal {
namespace {

constexpr int kIds = 100'000;

std::string Id(const char* prefix, int i) {
  // Not `prefix + std::to_string(i)`: GCC 12 warns falsely (-Wrestrict).
  return std::string(prefix).append(std::to_string(i));
}

TEST(CoilIdFilterTest, EmptyContainsNothing) {
  CoilIdFilter f;
  EXPECT_EQ(f.size(), 0u);
  EXPECT_FALSE(f.MayContain("K1"));
  EXPECT_FALSE(f.MayContain(""));
}

TEST(CoilIdFilterTest, InsertThenContains) {
  CoilIdFilter f;
  f.Insert("K1");
  f.Insert("K2");
  f.Insert("");
  EXPECT_TRUE(f.MayContain("K1"));
  EXPECT_TRUE(f.MayContain("K2"));
  EXPECT_TRUE(f.MayContain(""));
  EXPECT_FALSE(f.MayContain("K3"));
  EXPECT_FALSE(f.MayContain("K1 "));
  f.Insert("K1");  // a set: a second insert adds nothing
  EXPECT_EQ(f.size(), 3u);
}

TEST(CoilIdFilterTest, HashIsNeverZero) {
  EXPECT_NE(CoilIdFilter::Hash(""), 0u);
  EXPECT_EQ(CoilIdFilter::Hash("K1"), CoilIdFilter::Hash(std::string("K1")));
  EXPECT_NE(CoilIdFilter::Hash("K1"), CoilIdFilter::Hash("K2"));
  // 0 is the empty slot: it is stored and found as 1.
  CoilIdFilter f;
  f.InsertHash(0);
  EXPECT_TRUE(f.MayContainHash(0));
  EXPECT_TRUE(f.MayContainHash(1));
  EXPECT_EQ(f.size(), 1u);
}

TEST(CoilIdFilterTest, GrowthKeepsEveryIdAndTheLoadAtMostHalf) {
  CoilIdFilter f;
  size_t capacity = f.capacity();
  int doublings = 0;
  for (int i = 0; i < kIds; ++i) {
    f.Insert(Id("K", i));
    if (f.capacity() != capacity) {
      EXPECT_EQ(f.capacity(), 2 * capacity) << "after " << i + 1 << " ids";
      capacity = f.capacity();
      ++doublings;
      // Nothing inserted before the rehash is lost.
      for (int j = 0; j <= i; ++j) {
        ASSERT_TRUE(f.MayContain(Id("K", j))) << j << " after rehash at " << i;
      }
    }
    ASSERT_LE(2 * f.size(), f.capacity());
  }
  EXPECT_GE(doublings, 10);
  EXPECT_TRUE(std::has_single_bit(f.capacity()));
  EXPECT_EQ(f.size(), static_cast<size_t>(kIds));
  for (int i = 0; i < kIds; ++i) {
    ASSERT_TRUE(f.MayContain(Id("K", i))) << i;  // no false negatives
  }
}

TEST(CoilIdFilterTest, AbsentIdsAreAlmostNeverReported) {
  CoilIdFilter f;
  for (int i = 0; i < kIds; ++i) f.Insert(Id("K", i));
  // Ids close to the stored ones (same prefix, next numbers) and others.
  int false_positives = 0;
  for (int i = 0; i < kIds; ++i) {
    false_positives += f.MayContain(Id("K", kIds + i)) ? 1 : 0;
    false_positives += f.MayContain(Id("A", i)) ? 1 : 0;
  }
  // Only a full 64-bit collision answers true: expected 2e5 * 1e5 / 2^64
  // ~ 1e-9 false positives here.
  EXPECT_LE(false_positives, 1);
}

TEST(CoilIdFilterTest, CollidingSlotsProbeAndWrapAround) {
  CoilIdFilter f;
  ASSERT_EQ(f.capacity(), 16u);
  // All pick the last slot (low 4 bits 1111): they fill it and wrap to
  // slots 0 and 1.
  f.InsertHash(15);
  f.InsertHash(31);
  f.InsertHash(47);
  EXPECT_TRUE(f.MayContainHash(15));
  EXPECT_TRUE(f.MayContainHash(31));
  EXPECT_TRUE(f.MayContainHash(47));
  EXPECT_FALSE(f.MayContainHash(63));  // same start, probe ends empty
  EXPECT_FALSE(f.MayContainHash(16));  // slot 0 is taken by 31
  f.InsertHash(16);
  EXPECT_TRUE(f.MayContainHash(16));
  // Through several rehashes the chain is rebuilt, not lost.
  for (uint64_t h = 1000; h < 1200; ++h) f.InsertHash(h);
  for (uint64_t h : {15, 31, 47, 16}) EXPECT_TRUE(f.MayContainHash(h)) << h;
  EXPECT_FALSE(f.MayContainHash(63));
  EXPECT_EQ(f.size(), 204u);
}

TEST(CoilIdFilterTest, ReserveSizesOnceAndKeepsContent) {
  CoilIdFilter f;
  f.Insert("K0");
  f.Reserve(1000);
  EXPECT_EQ(f.capacity(), 2048u);  // smallest power of 2 >= 2 * 1000
  EXPECT_TRUE(f.MayContain("K0"));
  for (int i = 1; i < 1000; ++i) f.Insert(Id("K", i));
  EXPECT_EQ(f.capacity(), 2048u);
  f.Reserve(10);  // never shrinks
  EXPECT_EQ(f.capacity(), 2048u);
  for (int i = 0; i < 1000; ++i) EXPECT_TRUE(f.MayContain(Id("K", i))) << i;
}

}  // namespace
}  // namespace rollwear::storage::internal
