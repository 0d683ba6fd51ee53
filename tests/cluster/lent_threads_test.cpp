#include "cluster/lent_threads.hpp"

#include <gtest/gtest.h>

namespace codesign::cluster {
namespace {

TEST(LentThreads, APoolHasRoomForTheMachinesThreadsItCanUse) {
  // Two ranks of one thread on two cores, 20 environments each: room for the other rank's thread.
  EXPECT_EQ(pool_threads(1, 2, 20, 2), 2u);
  // No more than the cores the process may run on (bound to one core: nothing to take up)...
  EXPECT_EQ(pool_threads(1, 2, 20, 1), 1u);
  EXPECT_EQ(pool_threads(2, 16, 20, 8), 8u);
  // ...nor than its environments (a share of one has nothing to give a second thread)...
  EXPECT_EQ(pool_threads(1, 3, 1, 4), 1u);
  EXPECT_EQ(pool_threads(2, 3, 3, 0), 3u);  // cores unknown: no limit from them
  // ...but never fewer than its own threads, and a rank alone on its machine keeps its own.
  EXPECT_EQ(pool_threads(4, 2, 2, 2), 4u);
  EXPECT_EQ(pool_threads(2, 1, 20, 32), 2u);
  EXPECT_EQ(pool_threads(0, 2, 20, 2), 0u);  // 0: every core already
}

TEST(LentThreads, EachFinishedRankLendsItsThreadsUpToThePool) {
  EXPECT_EQ(threads_in_use(1, 0, 2), 1u);
  EXPECT_EQ(threads_in_use(1, 1, 2), 2u);
  EXPECT_EQ(threads_in_use(1, 2, 2), 2u);  // the pool is the limit
  EXPECT_EQ(threads_in_use(2, 1, 8), 4u);
  EXPECT_EQ(threads_in_use(2, 3, 8), 8u);
  EXPECT_EQ(threads_in_use(0, 1, 3), 3u);  // own 0: the whole pool
}

TEST(LentThreads, TheProcessMayRunOnAtLeastOneCore) { EXPECT_GE(cpus_of_this_process(), 1u); }

}  // namespace
}  // namespace codesign::cluster
