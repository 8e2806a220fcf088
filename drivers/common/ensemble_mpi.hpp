// ensemble_mpi.hpp — scale-out of ensemble sweeps over MPI ranks (docs/scale-out.md).
//
// A sweep driver (obstacles, hopper) lists its independent work items (sweep point × replica, or
// --vary value × orifice width) in one fixed order; every rank takes a deterministic shard of them,
// runs it as it would run the whole sweep alone, and rank 0 gathers the results and writes the
// result files.
// Each item carries its own seed, so its result does not depend on the rank that ran it.
//
// This is the only file that knows about MPI: ensemble_mpi.cpp is compiled with MESOFLOW_HAVE_MPI
// when CMake finds MPI (option MESOFLOW_ENABLE_MPI); without it, Ranks is one rank of one and every
// call below is the single-process identity, so the drivers have no MPI branches of their own.
// Host-side only: nothing here runs inside a kernel.
#pragma once

#include <cstddef>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace mesoflow::ensemble {

// True when this build talks MPI (MESOFLOW_HAVE_MPI).
bool built_with_mpi();

// The processes of one sweep. Kokkos must be initialized after start() and finalized before
// finish() (MPI_Init before Kokkos::initialize, Kokkos::finalize before MPI_Finalize), so a driver
// holds Ranks outside its KokkosScope:
//
//   mesoflow::ensemble::Ranks ranks;
//   const int code = app.run(argc, argv, [&] { ranks.start(); mesoflow::KokkosScope kokkos(n); ... });
//   return ranks.finish(code);
class Ranks {
 public:
  Ranks() = default;
  Ranks(const Ranks&) = delete;
  Ranks& operator=(const Ranks&) = delete;
  // MPI_Finalize if start() ran and finish() did not.
  ~Ranks();

  // MPI_Init (MPI builds; a process started without mpirun/srun is a singleton of size 1).
  void start();
  // Ends MPI with the driver's exit code: a failed rank of a multi-rank run calls MPI_Abort (so no
  // other rank waits forever in a collective for it), otherwise MPI_Finalize. Returns exit_code.
  int finish(int exit_code);

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool root() const { return rank_ == 0; }

  // Waits for every rank.
  void barrier() const;
  // The byte strings of all ranks, in rank order, on rank 0; an empty list on the other ranks.
  std::vector<std::vector<char>> gather(const std::vector<char>& mine) const;
  // The sum over ranks of `value`, on every rank.
  long long sum(long long value) const;

 private:
  bool started_ = false, finished_ = false;
  int rank_ = 0, size_ = 1;
};

// The items this rank runs out of `items` work items in their fixed order: item i goes to rank
// i mod size (round robin, so every rank gets a share of every sweep point of a point-major list).
std::vector<std::size_t> shard(std::size_t items, int rank, int size);

// This rank's share of the unfinished items of a (point, replica) sweep: the pairs for which
// is_done(point, replica) is false, listed point-major, dealt by shard(); by point, replica indices.
template <class IsDone>
std::vector<std::vector<int>> pending_shard(std::size_t points, int replicas, const Ranks& ranks, IsDone&& is_done) {
  std::vector<std::pair<int, int>> pending;
  for (std::size_t p = 0; p < points; ++p)
    for (int j = 0; j < replicas; ++j)
      if (!is_done(p, j)) pending.emplace_back(int(p), j);
  std::vector<std::vector<int>> todo(points);
  for (const std::size_t i : shard(pending.size(), ranks.rank(), ranks.size()))
    todo[std::size_t(pending[i].first)].push_back(pending[i].second);
  return todo;
}

// Byte strings of trivially copyable records (all ranks run the same build on one architecture).
template <class T>
void append_bytes(std::vector<char>& out, const T& value) {
  static_assert(std::is_trivially_copyable_v<T>, "append_bytes: trivially copyable types only");
  const char* p = reinterpret_cast<const char*>(&value);
  out.insert(out.end(), p, p + sizeof(T));
}

// Throws std::runtime_error when [offset, offset + size) is not inside `available` bytes.
void check_bytes(std::size_t offset, std::size_t size, std::size_t available);

// Reads back what append_bytes wrote, from `offset` on; throws std::runtime_error past the end.
template <class T>
T read_bytes(const std::vector<char>& in, std::size_t& offset) {
  static_assert(std::is_trivially_copyable_v<T>, "read_bytes: trivially copyable types only");
  check_bytes(offset, sizeof(T), in.size());
  T value;
  std::memcpy(&value, in.data() + offset, sizeof(T));
  offset += sizeof(T);
  return value;
}

// The `count` work items that rank 0 gathered (`gathered`: per rank, each item's index as
// append_bytes wrote it, then the item as T::append_bytes wrote it, read by T::read_bytes), in item
// order; an index out of range is an error naming `who`.
template <class T>
std::vector<T> read_items(const std::vector<std::vector<char>>& gathered, std::size_t count, const std::string& who) {
  std::vector<T> items(count);
  for (const std::vector<char>& bytes : gathered)
    for (std::size_t offset = 0; offset < bytes.size();) {
      const auto k = read_bytes<std::size_t>(bytes, offset);
      if (k >= items.size()) throw std::runtime_error(who + ": a rank sent work item " + std::to_string(k));
      items[k].read_bytes(bytes, offset);
    }
  return items;
}

}  // namespace mesoflow::ensemble
