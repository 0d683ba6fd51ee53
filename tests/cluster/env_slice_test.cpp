// How the ψ environments of an iteration are split over MPI ranks (cluster/mpi_env_pool.hpp):
// contiguous slices covering every environment once, sizes differing by at most one, the larger
// first; rank counts that leave a rank without an environment refused.
#include <gtest/gtest.h>

#include <stdexcept>

#include "cluster/mpi_env_pool.hpp"

namespace {

using codesign::cluster::env_slice;
using codesign::cluster::EnvSlice;

TEST(EnvSlice, SlicesCoverEveryEnvironmentOnceInOrder) {
  for (std::size_t n : {1u, 2u, 4u, 7u, 40u, 41u}) {
    for (int ranks = 1; ranks <= static_cast<int>(std::min<std::size_t>(n, 9)); ++ranks) {
      std::size_t next = 0, largest = 0, smallest = n;
      for (int r = 0; r < ranks; ++r) {
        const EnvSlice s = env_slice(n, r, ranks);
        EXPECT_EQ(s.first, next) << n << " envs, rank " << r << " of " << ranks;
        EXPECT_GE(s.count, 1u);
        if (r > 0) {
          EXPECT_LE(s.count, env_slice(n, r - 1, ranks).count);  // the larger slices first
        }
        largest = std::max(largest, s.count);
        smallest = std::min(smallest, s.count);
        next = s.first + s.count;
      }
      EXPECT_EQ(next, n);
      EXPECT_LE(largest - smallest, 1u);
    }
  }
  // 40 environments (the paper's ψ) on 16 ranks: 8 ranks of 3, then 8 of 2.
  EXPECT_EQ(env_slice(40, 7, 16).count, 3u);
  EXPECT_EQ(env_slice(40, 8, 16).count, 2u);
  EXPECT_EQ(env_slice(40, 8, 16).first, 24u);
}

TEST(EnvSlice, RankCountsThatLeaveARankEmptyAreRefused) {
  EXPECT_THROW(env_slice(4, 0, 5), std::invalid_argument);
  EXPECT_THROW(env_slice(4, 0, 0), std::invalid_argument);
  EXPECT_THROW(env_slice(4, 2, 2), std::invalid_argument);
  EXPECT_THROW(env_slice(4, -1, 2), std::invalid_argument);
}

}  // namespace
