// ranks.hpp — the processes of an MPI job (`mpirun -np P cdpowder compact …`), the few
// operations the engine needs of them, and one rank when the library is built without MPI
// (CDPOWDER_MPI=OFF) or the program was not started by an MPI launcher. MPI stays inside
// ranks.cpp: no other header includes mpi.h.
//
// Every operation here is collective: every rank calls it at the same point of the same work.
// The engine's work is the same on every rank up to which tiles a rank solves
// (solver/nlgs/tile_ranks.hpp), so the points match.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace cdpowder {

/// Starts MPI when the library has it and this process was started by an MPI launcher
/// (mpirun, mpiexec, srun: it set OMPI_COMM_WORLD_SIZE, PMI_SIZE or PMIX_RANK), with
/// MPI_THREAD_FUNNELED (OpenMP threads never call MPI); ends it when destroyed. One per
/// program, first thing in main. Without a launcher the program is one rank and MPI is not
/// started (a singleton start costs a second and prints warnings in containers).
class RankSession {
 public:
  RankSession(int& argc, char**& argv);
  ~RankSession();
  RankSession(const RankSession&) = delete;
  RankSession& operator=(const RankSession&) = delete;
  RankSession(RankSession&&) = delete;
  RankSession& operator=(RankSession&&) = delete;
};

/// Why a run (compact, simulate, resume) must not go on as a job of its own though a launcher
/// started this process as one of several copies, each of which would run the whole job into
/// the same folder; "" when it may. Slurm's srun without an MPI plugin (--mpi=none, its usual
/// default) starts copies with no launcher variable, only SLURM_STEP_NUM_TASKS; a build without
/// MPI cannot join mpirun's ranks. Not a question for a sweep's --task runners, which are
/// meant to run side by side.
[[nodiscard]] std::string copies_without_ranks();

/// Whether this build has MPI ranks (CMake found MPI and CDPOWDER_MPI was not OFF).
[[nodiscard]] bool ranks_built();

/// The job's ranks: 1 without MPI.
[[nodiscard]] int rank_count();

/// This process's rank, 0 … rank_count() − 1: 0 without MPI. Rank 0 writes the outputs.
[[nodiscard]] int this_rank();

/// Whether `flag` is true on any rank (a stop asked for by a signal that reached one rank).
[[nodiscard]] bool any_rank(bool flag);

/// A message of this rank's exchange: the bytes go to (or come from) rank `peer`.
struct RankBytes {
  int peer = 0;
  std::span<std::byte> bytes;
};

/// Sends every `sends[i].bytes` to its peer and receives every `receives[i].bytes` from its
/// peer, all at once; returns when all are done. Each receive must have a matching send of
/// the same size on its peer, with the same `tag`.
void exchange_with_ranks(std::span<const RankBytes> sends, std::span<const RankBytes> receives,
                         int tag);

/// Every rank's `mine` to every rank, in rank order: `all` receives rank 0's bytes, then
/// rank 1's, …; `counts[r]` is the size of rank r's (every rank passes the same counts).
void gather_from_all_ranks(std::span<const std::byte> mine, std::span<std::byte> all,
                           std::span<const int> counts);

}  // namespace cdpowder
