// Internal to storage: the set of 64-bit hashes of every committed coil id,
// so that MillStore admits a new coil (the common case of POST /v1/coils)
// without asking SQLite whether its id is stored.
//
// MayContain(id) == false proves the id is not stored. true means "probably
// stored": the caller confirms with the database (LookupCoil), so a false
// positive (another stored id with the same 64-bit hash; for n stored ids
// an absent id collides with probability about n / 2^64) costs one SQLite
// lookup and never a wrong answer.
//
// Layout: open addressing with linear probing in a flat array of hashes
// (slot value 0 = empty, so a hash of 0 is stored as 1), power-of-two
// capacity, load factor <= 1/2, capacity doubled when an insert would pass
// it. Memory: 8 bytes per slot at a load of 1/4..1/2, i.e. 16 to 32 bytes
// per stored coil (10 million coils: 160-320 MB); while growing, the old
// array (half the size) exists alongside the new one.
//
// Thread-safety: not thread-safe; MillStoreImpl guards it with its mu_.
#ifndef ROLLWEAR_STORAGE_COIL_ID_FILTER_H_
#define ROLLWEAR_STORAGE_COIL_ID_FILTER_H_

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

namespace rollwear::storage::internal {

class CoilIdFilter {
 public:
  CoilIdFilter();

  // The hash stored for `id`: FNV-1a 64 over its bytes, then murmur3's
  // fmix64 (so the low bits that pick the slot depend on every byte), 0
  // mapped to 1. Never 0.
  static uint64_t Hash(std::string_view id);

  void Insert(std::string_view id) { InsertHash(Hash(id)); }
  bool MayContain(std::string_view id) const {
    return MayContainHash(Hash(id));
  }

  // The same on a hash as Hash() returns (0 is taken as 1); used by the
  // above and by tests that need chosen collisions.
  void InsertHash(uint64_t hash);
  bool MayContainHash(uint64_t hash) const;

  // Grows the table once so that `n` distinct hashes fit without a rehash.
  void Reserve(size_t n);

  size_t size() const { return size_; }              // distinct hashes stored
  size_t capacity() const { return slots_.size(); }  // slots, a power of 2

 private:
  // Index of the slot holding `hash`, or of the empty slot ending its
  // probe sequence.
  size_t FindSlot(uint64_t hash) const;
  // Rehashes every stored hash into `new_capacity` slots (a power of 2).
  void Rehash(size_t new_capacity);

  std::vector<uint64_t> slots_;
  size_t size_ = 0;
};

}  // namespace rollwear::storage::internal

#endif  // ROLLWEAR_STORAGE_COIL_ID_FILTER_H_
