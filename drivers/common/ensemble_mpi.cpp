// ensemble_mpi.cpp — Ranks over MPI_COMM_WORLD when built with MESOFLOW_HAVE_MPI, else one rank.
#include "drivers/common/ensemble_mpi.hpp"

#include <climits>
#include <cstdlib>
#include <iostream>
#include <stdexcept>

#ifdef MESOFLOW_HAVE_MPI
#include <mpi.h>
#endif

namespace mesoflow::ensemble {

bool built_with_mpi() {
#ifdef MESOFLOW_HAVE_MPI
  return true;
#else
  return false;
#endif
}

#ifdef MESOFLOW_HAVE_MPI

namespace {
void check(int status, const char* call) {
  if (status != MPI_SUCCESS) throw std::runtime_error(std::string("mesoflow::ensemble: ") + call + " failed");
}
}  // namespace

Ranks::~Ranks() {
  int finalized = 0;
  if (started_ && !finished_ && MPI_Finalized(&finalized) == MPI_SUCCESS && !finalized) MPI_Finalize();
}

void Ranks::start() {
  if (started_) throw std::logic_error("mesoflow::ensemble::Ranks: started twice");
  check(MPI_Init(nullptr, nullptr), "MPI_Init");
  started_ = true;
  check(MPI_Comm_rank(MPI_COMM_WORLD, &rank_), "MPI_Comm_rank");
  check(MPI_Comm_size(MPI_COMM_WORLD, &size_), "MPI_Comm_size");
}

int Ranks::finish(int exit_code) {
  if (!started_ || finished_) return exit_code;
  finished_ = true;
  std::cout.flush();
  std::cerr.flush();
  if (exit_code != 0 && size_ > 1) MPI_Abort(MPI_COMM_WORLD, exit_code);
  MPI_Finalize();
  return exit_code;
}

void Ranks::barrier() const {
  if (started_) check(MPI_Barrier(MPI_COMM_WORLD), "MPI_Barrier");
}

std::vector<std::vector<char>> Ranks::gather(const std::vector<char>& mine) const {
  if (!started_ || size_ == 1) return {mine};
  if (mine.size() > std::size_t(INT_MAX)) throw std::runtime_error("mesoflow::ensemble: gather of more than 2 GiB");
  const int count = int(mine.size());
  std::vector<int> counts(root() ? std::size_t(size_) : 0), displacements(counts.size());
  check(MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD), "MPI_Gather");
  long long total = 0;
  for (std::size_t r = 0; r < counts.size(); ++r) {
    displacements[r] = int(total);
    total += counts[r];
  }
  if (total > INT_MAX) throw std::runtime_error("mesoflow::ensemble: gather of more than 2 GiB");
  std::vector<char> all(static_cast<std::size_t>(total));
  check(MPI_Gatherv(mine.data(), count, MPI_CHAR, all.data(), counts.data(), displacements.data(), MPI_CHAR, 0,
                    MPI_COMM_WORLD),
        "MPI_Gatherv");
  std::vector<std::vector<char>> out;
  for (std::size_t r = 0; r < counts.size(); ++r)
    out.emplace_back(all.begin() + displacements[r], all.begin() + displacements[r] + counts[r]);
  return out;
}

long long Ranks::sum(long long value) const {
  if (!started_ || size_ == 1) return value;
  long long total = 0;
  check(MPI_Allreduce(&value, &total, 1, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD), "MPI_Allreduce");
  return total;
}

#else  // one rank of one

Ranks::~Ranks() = default;

// Started as one of several processes by an MPI launcher (OpenMPI's mpirun sets
// OMPI_COMM_WORLD_SIZE, MPICH's hydra PMI_SIZE), every process would run the whole sweep and
// write the same files: refused.
void Ranks::start() {
  if (started_) throw std::logic_error("mesoflow::ensemble::Ranks: started twice");
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
    const char* value = std::getenv(name);
    if (value != nullptr && std::atoi(value) > 1)
      throw std::runtime_error(std::string("started as one of ") + value +
                               " MPI processes, but this build has no MPI (MESOFLOW_ENABLE_MPI=OFF): every process "
                               "would run the whole sweep; run it without mpirun, or rebuild with MPI "
                               "(docs/scale-out.md)");
  }
  started_ = true;
}

int Ranks::finish(int exit_code) {
  finished_ = true;
  return exit_code;
}

void Ranks::barrier() const {}

std::vector<std::vector<char>> Ranks::gather(const std::vector<char>& mine) const { return {mine}; }

long long Ranks::sum(long long value) const { return value; }

#endif

std::vector<std::size_t> shard(std::size_t items, int rank, int size) {
  if (size < 1 || rank < 0 || rank >= size)
    throw std::invalid_argument("mesoflow::ensemble::shard: rank " + std::to_string(rank) + " of " +
                                std::to_string(size));
  std::vector<std::size_t> mine;
  for (std::size_t i = std::size_t(rank); i < items; i += std::size_t(size)) mine.push_back(i);
  return mine;
}

void check_bytes(std::size_t offset, std::size_t size, std::size_t available) {
  if (offset > available || size > available - offset)
    throw std::runtime_error("mesoflow::ensemble: a gathered record is truncated (" + std::to_string(available) +
                             " bytes, " + std::to_string(offset + size) + " needed)");
}

}  // namespace mesoflow::ensemble
