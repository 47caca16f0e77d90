// The ranks of a job in one process (the multi-rank behaviour is tested by mpi_run_test.sh under
// mpirun): the shared counter hands out 0, 1, 2, ... once each, shards parse and own their items.
#include "rabbit/scenario/ranks.h"

#include <gtest/gtest.h>

#include <string>

namespace rabbit {
namespace {

TEST(SharedCounter, HandsOutEachIndexOnceInOrder) {
  ASSERT_EQ(Ranks::size(), 1);
  SharedCounter counter;
  for (long long k = 0; k < 1000; ++k) ASSERT_EQ(counter.Next(), k);
  SharedCounter fresh;  // a new counter starts again at 0
  EXPECT_EQ(fresh.Next(), 0);
}

TEST(Shard, ParsesAndOwnsItsItems) {
  Shard shard;
  std::string error;
  ASSERT_TRUE(ParseShard("2/3", &shard, &error)) << error;
  EXPECT_TRUE(shard.active());
  EXPECT_FALSE(shard.Owns(0));
  EXPECT_TRUE(shard.Owns(1));
  EXPECT_TRUE(shard.Owns(4));
  for (const char* bad : {"0/3", "4/3", "3", "a/b", "1/0", ""}) {
    EXPECT_FALSE(ParseShard(bad, &shard, &error)) << bad;
    EXPECT_NE(error.find("--shard"), std::string::npos);
  }
}

}  // namespace
}  // namespace rabbit
