#include "storage/coil_id_filter.h"

#include <bit>
#include <utility>

namespace rollwear::storage::internal {
namespace {

constexpr size_t kMinCapacity = 16;
constexpr uint64_t kFnvOffsetBasis = 14695981039346656037ull;
constexpr uint64_t kFnvPrime = 1099511628211ull;

// murmur3's 64-bit finaliser: a bijection whose every output bit depends
// on every input bit.
uint64_t Fmix64(uint64_t k) {
  k ^= k >> 33;
  k *= 0xff51afd7ed558ccdull;
  k ^= k >> 33;
  k *= 0xc4ceb9fe1a85ec53ull;
  k ^= k >> 33;
  return k;
}

// Load factor <= 1/2: `n` hashes fit in `capacity` slots when 2n <= capacity.
bool Fits(size_t n, size_t capacity) { return 2 * n <= capacity; }

}  // namespace

CoilIdFilter::CoilIdFilter() : slots_(kMinCapacity, 0) {}

uint64_t CoilIdFilter::Hash(std::string_view id) {
  uint64_t h = kFnvOffsetBasis;
  for (const char c : id) {
    h ^= static_cast<unsigned char>(c);
    h *= kFnvPrime;
  }
  h = Fmix64(h);
  return h == 0 ? 1 : h;
}

size_t CoilIdFilter::FindSlot(uint64_t hash) const {
  // The table is never full (load <= 1/2), so the probe ends.
  const size_t mask = slots_.size() - 1;
  size_t i = static_cast<size_t>(hash) & mask;
  while (slots_[i] != 0 && slots_[i] != hash) i = (i + 1) & mask;
  return i;
}

void CoilIdFilter::InsertHash(uint64_t hash) {
  if (hash == 0) hash = 1;
  size_t i = FindSlot(hash);
  if (slots_[i] == hash) return;
  if (!Fits(size_ + 1, slots_.size())) {
    Rehash(2 * slots_.size());
    i = FindSlot(hash);
  }
  slots_[i] = hash;
  ++size_;
}

bool CoilIdFilter::MayContainHash(uint64_t hash) const {
  if (hash == 0) hash = 1;
  return slots_[FindSlot(hash)] == hash;
}

void CoilIdFilter::Reserve(size_t n) {
  if (Fits(n, slots_.size())) return;
  Rehash(std::bit_ceil(2 * n));
}

void CoilIdFilter::Rehash(size_t new_capacity) {
  std::vector<uint64_t> old(new_capacity, 0);
  slots_.swap(old);
  for (const uint64_t hash : old) {
    if (hash != 0) slots_[FindSlot(hash)] = hash;
  }
}

}  // namespace rollwear::storage::internal
