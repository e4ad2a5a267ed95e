// ranks.cpp — MPI, when built in (ranks.hpp); one rank otherwise.
#include "cdpowder/core/ranks.hpp"

#include <algorithm>
#include <array>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>

#if defined(CDPOWDER_WITH_MPI)
#include <mpi.h>
#endif

namespace cdpowder {

namespace {

/// Whether MPI was started by RankSession (and not yet ended).
bool g_started = false;
int g_rank = 0;
int g_ranks = 1;

/// Whether an MPI launcher started this process: Open MPI's mpirun, a PMI launcher (MPICH's
/// Hydra, Slurm's srun with PMI-2) or a PMIx one (srun --mpi=pmix, Open MPI 5).
bool started_by_launcher() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"}) {
    if (std::getenv(name) != nullptr) return true;
  }
  return false;
}

/// The value of the environment variable `name` as a count, 0 when unset or not a number.
long count_in(const char* name) {
  const char* text = std::getenv(name);
  if (text == nullptr) return 0;
  char* end = nullptr;
  const long value = std::strtol(text, &end, 10);
  return end != text && *end == '\0' ? value : 0;
}

#if defined(CDPOWDER_WITH_MPI)
void check(int code, const char* what) {
  if (code == MPI_SUCCESS) return;
  std::array<char, MPI_MAX_ERROR_STRING> text{};
  int length = 0;
  MPI_Error_string(code, text.data(), &length);
  throw std::runtime_error(std::string(what) + ": " +
                           std::string(text.data(), static_cast<std::size_t>(length)));
}
#endif

}  // namespace

RankSession::RankSession([[maybe_unused]] int& argc, [[maybe_unused]] char**& argv) {
#if defined(CDPOWDER_WITH_MPI)
  if (!started_by_launcher()) return;
  int provided = 0;
  check(MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
  g_started = true;
  // errors come back as codes (check() turns them into exceptions with MPI's message)
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_ranks);
#endif
}

RankSession::~RankSession() {
#if defined(CDPOWDER_WITH_MPI)
  if (g_started) MPI_Finalize();
  g_started = false;
  g_rank = 0;
  g_ranks = 1;
#endif
}

// Slurm's srun without an MPI plugin (--mpi=none, the usual default) starts the copies but
// sets none of the launcher variables, only SLURM_STEP_NUM_TASKS; a build without MPI sees
// mpirun's variables and could not join the ranks either.
std::string copies_without_ranks() {
  const long tasks = count_in("SLURM_STEP_NUM_TASKS");
  const long launched = std::max({count_in("OMPI_COMM_WORLD_SIZE"), count_in("PMI_SIZE"), tasks});
  if (launched <= 1) return {};
  if (!ranks_built()) {
    return "this cdpowder was built without MPI (CDPOWDER_MPI=OFF) and was started as one of " +
           std::to_string(launched) +
           " copies, each of which would run the whole job: run it as one process, or build "
           "it with MPI";
  }
  if (started_by_launcher()) return {};
  return "srun started " + std::to_string(tasks) +
         " copies of cdpowder without an MPI plugin, so each would run the whole job on its "
         "own: run `srun --mpi=pmix …` (or export SLURM_MPI_TYPE=pmix; docs/parallel.md, "
         "\"Slurm\")";
}

bool ranks_built() {
#if defined(CDPOWDER_WITH_MPI)
  return true;
#else
  return false;
#endif
}

int rank_count() {
  return g_ranks;
}

int this_rank() {
  return g_rank;
}

bool any_rank(bool flag) {
#if defined(CDPOWDER_WITH_MPI)
  if (g_ranks > 1) {
    int mine = flag ? 1 : 0;
    int any = 0;
    check(MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_LOR, MPI_COMM_WORLD), "MPI_Allreduce");
    return any != 0;
  }
#endif
  return flag;
}

void exchange_with_ranks(std::span<const RankBytes> sends, std::span<const RankBytes> receives,
                         [[maybe_unused]] int tag) {
#if defined(CDPOWDER_WITH_MPI)
  if (g_ranks > 1) {
    std::vector<MPI_Request> requests(sends.size() + receives.size(), MPI_REQUEST_NULL);
    std::size_t r = 0;
    for (const RankBytes& in : receives) {
      check(MPI_Irecv(in.bytes.data(), static_cast<int>(in.bytes.size()), MPI_BYTE, in.peer, tag,
                      MPI_COMM_WORLD, &requests[r++]),
            "MPI_Irecv");
    }
    for (const RankBytes& out : sends) {
      check(MPI_Isend(out.bytes.data(), static_cast<int>(out.bytes.size()), MPI_BYTE, out.peer, tag,
                      MPI_COMM_WORLD, &requests[r++]),
            "MPI_Isend");
    }
    check(MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE),
          "MPI_Waitall");
    return;
  }
#endif
  if (!sends.empty() || !receives.empty()) {
    throw std::logic_error("exchange_with_ranks: messages in a job of one rank");
  }
}

void gather_from_all_ranks(std::span<const std::byte> mine, std::span<std::byte> all,
                           std::span<const int> counts) {
#if defined(CDPOWDER_WITH_MPI)
  if (g_ranks > 1) {
    std::vector<int> displacements(counts.size(), 0);
    for (std::size_t r = 1; r < counts.size(); ++r) {
      displacements[r] = displacements[r - 1] + counts[r - 1];
    }
    check(MPI_Allgatherv(mine.data(), static_cast<int>(mine.size()), MPI_BYTE, all.data(),
                         counts.data(), displacements.data(), MPI_BYTE, MPI_COMM_WORLD),
          "MPI_Allgatherv");
    return;
  }
#endif
  if (!mine.empty()) std::memcpy(all.data(), mine.data(), mine.size());
}

}  // namespace cdpowder
