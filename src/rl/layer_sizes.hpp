#pragma once
// Layer sizes of an MLP (mlp.hpp) from its input size, hidden sizes and output size:
// {in, hidden..., out}. Shared by the feed-forward and the recurrent actor-critic, and by the
// check of a policy file against a config.
#include <vector>

namespace codesign::rl {

inline std::vector<int> layer_sizes(int in, const std::vector<int>& hidden, int out) {
  std::vector<int> sizes{in};
  sizes.insert(sizes.end(), hidden.begin(), hidden.end());
  sizes.push_back(out);
  return sizes;
}

// The inverse: the hidden sizes of a layer-size list {in, hidden..., out}.
inline std::vector<int> hidden_sizes(const std::vector<int>& sizes) {
  return sizes.size() < 2 ? std::vector<int>{} : std::vector<int>(sizes.begin() + 1, sizes.end() - 1);
}

}  // namespace codesign::rl
