// Tests of the host-side pieces of drivers/common/ensemble_mpi.hpp that need no MPI launcher: the
// round-robin shard of work items, the byte records ranks send to rank 0, and a Ranks that was not
// started (one rank of one). Sweeps over real ranks are tested by tests/drivers/*_mpi.sh.
#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <vector>

#include "drivers/common/ensemble_mpi.hpp"

namespace mesoflow::ensemble {
namespace {

TEST(EnsembleShard, DealsEveryItemToExactlyOneRankRoundRobin) {
  for (int size = 1; size <= 5; ++size)
    for (std::size_t items = 0; items <= 13; ++items) {
      std::vector<int> owner(items, -1);
      std::size_t smallest = items, largest = 0;
      for (int rank = 0; rank < size; ++rank) {
        const std::vector<std::size_t> mine = shard(items, rank, size);
        smallest = std::min(smallest, mine.size());
        largest = std::max(largest, mine.size());
        for (std::size_t n = 0; n < mine.size(); ++n) {
          ASSERT_LT(mine[n], items);
          EXPECT_EQ(mine[n], std::size_t(rank) + n * std::size_t(size)) << "ascending, every size-th item";
          EXPECT_EQ(owner[mine[n]], -1) << "item " << mine[n] << " dealt twice";
          owner[mine[n]] = rank;
        }
      }
      for (std::size_t i = 0; i < items; ++i) EXPECT_NE(owner[i], -1) << "item " << i << " of " << items << " not dealt";
      EXPECT_LE(largest - smallest, 1u) << "shares differ by at most one item";
    }
}

TEST(EnsembleShard, RefusesARankOutsideTheRun) {
  EXPECT_THROW(shard(4, 2, 2), std::invalid_argument);
  EXPECT_THROW(shard(4, -1, 2), std::invalid_argument);
  EXPECT_THROW(shard(4, 0, 0), std::invalid_argument);
}

struct Record {
  int index;
  std::uint64_t seed;
  double value;
  bool flag;
};

TEST(EnsembleBytes, RecordsRoundTripBitwiseAndATruncatedOneThrows) {
  const std::vector<Record> sent = {{3, 0xFFFFFFFFFFFFFFFFULL, 0.1, true}, {-7, 42, -1e-300, false}, {0, 1, 2.5, true}};
  std::vector<char> bytes;
  for (const Record& r : sent) append_bytes(bytes, r);
  append_bytes(bytes, std::size_t(9));
  ASSERT_EQ(bytes.size(), 3 * sizeof(Record) + sizeof(std::size_t));
  std::size_t offset = 0;
  for (const Record& r : sent) {
    const Record got = read_bytes<Record>(bytes, offset);
    EXPECT_EQ(got.index, r.index);
    EXPECT_EQ(got.seed, r.seed);
    EXPECT_EQ(got.value, r.value);  // bitwise: the same double
    EXPECT_EQ(got.flag, r.flag);
  }
  EXPECT_EQ(read_bytes<std::size_t>(bytes, offset), 9u);
  EXPECT_EQ(offset, bytes.size());
  EXPECT_THROW(read_bytes<char>(bytes, offset), std::runtime_error);
  bytes.pop_back();
  offset = 3 * sizeof(Record);
  EXPECT_THROW(read_bytes<std::size_t>(bytes, offset), std::runtime_error);
}

TEST(EnsembleRanks, NotStartedIsOneRankOfOne) {
  Ranks ranks;
  EXPECT_EQ(ranks.rank(), 0);
  EXPECT_EQ(ranks.size(), 1);
  EXPECT_TRUE(ranks.root());
  const std::vector<char> mine = {'a', 'b', '\0', 'c'};
  const std::vector<std::vector<char>> all = ranks.gather(mine);
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0], mine);
  EXPECT_EQ(ranks.sum(-12), -12);
  ranks.barrier();
  EXPECT_EQ(ranks.finish(3), 3);
}

}  // namespace
}  // namespace mesoflow::ensemble
