// Grid cells in open-addressed hash tables: index lists per cell (the face
// grid's storage, face_grid.h) and a set of cells (the free-room walk's,
// channel_width.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "gdm/cell_hash.h"

namespace gdm {

// A key's first slot in a table of 2^bits entries (bits in [1, 63]): the top
// bits of a multiplicative (Fibonacci) hash. Both tables below probe
// linearly from there and stay at most half full.
inline std::size_t cell_slot(CellKey key, int bits) {
  return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> (64 - bits));
}

// Linear probing over a power-of-two table kept at most half full, keys mixed
// by a multiplicative (Fibonacci) hash. A lookup is a multiply, a shift and
// mostly one probe of a flat key array; std::unordered_map took a division by
// a prime and a node pointer per lookup (3 % of the CT series' time went to its
// find() in the intersection guard's queries). A cell's list keeps the order
// its entries were added in, as before.
class CellLists {
 public:
  // The cell's list, or nullptr when no entry was ever added to the cell.
  const std::vector<int>* find(CellKey key) const {
    if (keys_.empty()) return nullptr;
    for (std::size_t i = slot(key);; i = (i + 1) & mask()) {
      if (keys_[i] == key) return &lists_[i];
      if (keys_[i] == kEmpty) return nullptr;
    }
  }
  std::vector<int>* find(CellKey key) {
    return const_cast<std::vector<int>*>(static_cast<const CellLists&>(*this).find(key));
  }
  // The cell's list, created empty when absent.
  std::vector<int>& operator[](CellKey key) {
    if (2 * (used_ + 1) > keys_.size()) grow();
    std::size_t i = slot(key);
    for (; keys_[i] != key; i = (i + 1) & mask())
      if (keys_[i] == kEmpty) {
        keys_[i] = key;
        ++used_;
        break;
      }
    return lists_[i];
  }
  // Empties every list; the cells and their storage stay for the next use.
  void clear_lists() {
    for (auto& list : lists_) list.clear();
  }
  // Cells created so far.
  std::size_t size() const { return used_; }

 private:
  // cell_key() uses 63 bits: no cell has this key.
  static constexpr CellKey kEmpty = ~CellKey{0};

  std::size_t mask() const { return keys_.size() - 1; }
  std::size_t slot(CellKey key) const { return cell_slot(key, 64 - shift_); }
  void grow() {
    const std::size_t capacity = keys_.empty() ? 1024 : 2 * keys_.size();
    std::vector<CellKey> keys(capacity, kEmpty);
    std::vector<std::vector<int>> lists(capacity);
    shift_ = 64;
    for (std::size_t c = capacity; c > 1; c >>= 1) --shift_;
    keys.swap(keys_);
    lists.swap(lists_);
    for (std::size_t j = 0; j < keys.size(); ++j) {
      if (keys[j] == kEmpty) continue;
      std::size_t i = slot(keys[j]);
      while (keys_[i] != kEmpty) i = (i + 1) & mask();
      keys_[i] = keys[j];
      lists_[i] = std::move(lists[j]);
    }
  }

  std::vector<CellKey> keys_;
  std::vector<std::vector<int>> lists_;
  std::size_t used_ = 0;
  int shift_ = 64;
};

// A set of cells for one pass of many short ones (each free-room walk): its
// table is kept, and each entry is stamped with the pass that added it, so a
// pass starts by counting the stamp up instead of clearing or allocating
// (std::unordered_set's allocations were most of the walks' time, issue 17).
class CellSet {
 public:
  // Empties the set (its storage stays).
  void start_pass() {
    if (table_.empty()) resize(8);
    if (++stamp_ == 0) {
      for (Entry& e : table_) e.stamp = 0;
      stamp_ = 1;
    }
    used_ = 0;
  }
  // Adds key; false when it was in the set already.
  bool insert(CellKey key) {
    if (2 * (used_ + 1) > table_.size()) resize(bits_ + 1);
    for (std::size_t i = cell_slot(key, bits_);; i = (i + 1) & (table_.size() - 1)) {
      Entry& e = table_[i];
      if (e.stamp != stamp_) {
        e = {key, stamp_};
        ++used_;
        return true;
      }
      if (e.key == key) return false;
    }
  }

 private:
  struct Entry {
    CellKey key = 0;
    std::uint32_t stamp = 0;  // the pass that added it; another pass's entry is a free slot
  };
  void resize(int bits) {
    std::vector<Entry> old(std::size_t{1} << bits);
    old.swap(table_);
    bits_ = bits;
    used_ = 0;
    for (const Entry& e : old)
      if (e.stamp == stamp_ && stamp_ != 0) insert(e.key);
  }

  std::vector<Entry> table_;
  int bits_ = 0;
  std::uint32_t stamp_ = 0;
  std::size_t used_ = 0;
};

}  // namespace gdm
