#pragma once
// Layer sizes of an MLP (mlp.hpp) from its input size, hidden sizes and output size:
// {in, hidden..., out}. Shared by the feed-forward and the recurrent actor-critic.
#include <vector>

namespace codesign::rl {

inline std::vector<int> layer_sizes(int in, const std::vector<int>& hidden, int out) {
  std::vector<int> sizes{in};
  sizes.insert(sizes.end(), hidden.begin(), hidden.end());
  sizes.push_back(out);
  return sizes;
}

}  // namespace codesign::rl
