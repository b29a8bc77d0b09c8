#pragma once
// Look-ups in a sorted map (std::map) for keys asked in ascending order: one walk over the map
// instead of a descent down its tree per key. Asking a key below the last one asked is misuse
// (it is then not found).

namespace hydra_multi {

template <class Map>
class AscendingLookup {
 public:
  explicit AscendingLookup(const Map& map) : it_(map.begin()), end_(map.end()) {}
  /// The value of `key`, or null.
  const typename Map::mapped_type* find(const typename Map::key_type& key) {
    while (it_ != end_ && it_->first < key) ++it_;
    return it_ != end_ && !(key < it_->first) ? &it_->second : nullptr;
  }

 private:
  typename Map::const_iterator it_, end_;
};

}  // namespace hydra_multi
