// gimp: explicit GIMP solid dynamics on a structured grid. See README.md and docs/.
#include "gimp/solver/solver.hpp"

#include "gimp/core/interrupt.hpp"
#include "gimp/input/options.hpp"
#include "gimp/input/options_file.hpp"
#include "gimp/input/validate.hpp"

#include <petscsys.h>

#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <set>
#include <string>
#include <thread>
#include <vector>

static const char help[] =
    "gimp: explicit Generalized Interpolation Material Point solver.\n"
    "Usage: gimp -options_file options/plate.opts [-ts_max_steps N] [-log_view]\n"
    "Options are listed below and in docs/options.md (SI units).\n";

namespace {

/// PETSc's error handler while the run steps: an out-of-memory error is noted (and printed by
/// main as one line), any other is PETSc's trace as before.
PetscErrorCode noteOutOfMemory(MPI_Comm comm, int line, const char *fun, const char *file,
                               PetscErrorCode n, PetscErrorType p, const char *mess, void *ctx) {
  if (n == PETSC_ERR_MEM) {
    *static_cast<bool *>(ctx) = true;
    return n;
  }
  return PetscTraceBackErrorHandler(comm, line, fun, file, n, p, mess, nullptr);
}

/// Run `steps` with noteOutOfMemory; PETSc's out-of-memory error leaves as std::bad_alloc.
template <class Steps> PetscErrorCode runWatchingMemory(Steps steps) {
  bool outOfMemory = false;
  PetscCall(PetscPushErrorHandler(noteOutOfMemory, &outOfMemory));
  PetscErrorCode ierr = PETSC_SUCCESS;
  try {
    ierr = steps();
  } catch (...) {
    PetscCall(PetscPopErrorHandler());
    throw;
  }
  PetscCall(PetscPopErrorHandler());
  if (ierr && outOfMemory) throw std::bad_alloc();
  return ierr;
}

/// Set up and run the solver of dimension D; the process's exit code: 3 for a run that went
/// unstable (its outputs written), 128 + the signal for an interrupted one (checkpoint, last
/// frame and summary written; as a shell reports a process the signal ended: 130 SIGINT, 143
/// SIGTERM), 1 for a PETSc error.
template <int D> int runScene() {
  gimp::Solver<D> sim(PETSC_COMM_WORLD);
  PetscErrorCode ierr = sim.setup();
  if (!ierr) ierr = runWatchingMemory([&] { return sim.run(); });
  if (ierr) return 1;
  if (sim.failed()) return 3;
  if (sim.interrupted()) return 128 + sim.interrupted();
  return 0;
}

/// Insert the scene's options (-gimp_*) after PetscInitialize, in order; the one error line when
/// PETSc's options database cannot hold them all (PETSc 3.18 holds 512 names), else "".
std::string insertSceneOptions(const std::vector<gimp::LateOption> &late) {
  if (PetscPushErrorHandler(PetscReturnErrorHandler, nullptr)) return "cannot set up PETSc";
  std::string full;
  for (const gimp::LateOption &o : late)
    if (PetscOptionsSetValue(nullptr, o.key.c_str(), o.hasValue ? o.value.c_str() : nullptr)) {
      full = o.key;
      break;
    }
  (void)PetscPopErrorHandler();
  if (full.empty()) return "";
  std::set<std::string> names;
  for (const gimp::LateOption &o : late) {
    std::string name = o.key;
    for (char &c : name)
      c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    names.insert(name);
  }
  return "option " + full + ": the scene gives " + std::to_string(names.size()) +
         " different options, more than PETSc's options database holds (512 names with the "
         "other options); give fewer (fewer probes, bodies or levels)";
}

/// An allocation failed (std::bad_alloc, or PETSc's out-of-memory error passed on as one): the
/// rank that met it says so; the other ranks may wait in a collective call, so under MPI the run
/// is aborted (every rank ends, exit 2). Ranks but 0 first give rank 0, which meets the same
/// allocation when the ranks share the work alike, two seconds to abort: one line, not one a rank.
void outOfMemory() {
  PetscMPIInt size = 1, rank = 0;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank > 0) std::this_thread::sleep_for(std::chrono::seconds(2));
  std::fprintf(stderr, "gimp: error: option -gimp_memory_limit: out of memory while setting up or "
                       "running the scene (the machine has less than the run needs); use a "
                       "coarser grid, fewer particles or more ranks, and keep -gimp_memory_limit "
                       "at or below the memory there is\n");
  std::fflush(stderr);
  if (size > 1) MPI_Abort(PETSC_COMM_WORLD, 2);
}

/// A process that no launcher started (gimp::launcherRank() < 0) is one rank alone. Open MPI
/// would probe for it the network transports (UCX) it might use to reach other processes: about
/// 0.25 s of wall time on a 2-core machine, more than the whole setup of most scenes, for a
/// process that talks to no other. So it asks for the ob1 transport layer (over the self and
/// shared-memory links), unless the user set OMPI_MCA_pml; other MPI libraries read no OMPI_MCA_
/// variable. A run under mpiexec or srun keeps what its launcher and the user chose. (The
/// singleton's runtime daemon is kept: an isolated singleton would skip it, but every isolated
/// process then takes the same job id, and two at once share, and remove at their end, the
/// session directory that MPI-IO keeps its shared file pointers in: HDF5 output fails.)
void startAlone() {
  if (gimp::launcherRank() >= 0) return;
  setenv("OMPI_MCA_pml", "ob1", 0);
}

} // namespace

int main(int argc, char **argv) {
  // -options_file names are read here, nested ones relative to the file that names them.
  // An error is found alike on every rank; MPI has not started: print it from rank 0.
  std::vector<std::string> args{argv[0]};
  gimp::SplitArgs split;
  try {
    split = gimp::splitForPetsc(gimp::expandOptionsFiles({argv + 1, argv + argc}));
    args.insert(args.end(), split.early.begin(), split.early.end());
  } catch (const gimp::InputError &e) {
    if (gimp::launcherRank() <= 0) std::fprintf(stderr, "gimp: error: %s\n", e.what());
    return 2;
  }
  std::vector<char *> cargs;
  for (std::string &a : args)
    cargs.push_back(a.data());
  cargs.push_back(nullptr);
  argc = static_cast<int>(args.size());
  argv = cargs.data();
  startAlone();
  // The scene's options are not on the command line MPI starts with (a long scene would not
  // fit there): inserted now, in their order; they override what comes before them on the
  // expanded command line as they did there (PETSc reads no -gimp_ option while it starts).
  PetscCall(PetscInitialize(&argc, &argv, nullptr, help));
  if (const std::string full = insertSceneOptions(split.late); !full.empty()) {
    PetscMPIInt rank = 0;
    MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
    if (rank == 0) std::fprintf(stderr, "gimp: error: %s\n", full.c_str());
    (void)PetscFinalize();
    return 2;
  }
  // After PetscInitialize: SIGINT and SIGTERM stop the run at the end of a step (ours replaces
  // any handler PETSc installed for them).
  if (!gimp::installInterruptHandlers())
    (void)PetscPrintf(PETSC_COMM_WORLD, "gimp: warning: cannot handle SIGINT/SIGTERM\n");
  int code = 0;
  try {
    PetscBool help = PETSC_FALSE;
    PetscCall(PetscOptionsHasHelp(nullptr, &help));
    PetscInt dim = 2;
    bool markdown = false; // -gimp_options_markdown [true|false]: a value is read as a flag's
    const PetscErrorCode ierr = gimp::readOptionsOneLine([&] {
      try {
        const gimp::input::Options options(PETSC_COMM_WORLD, 2, help);
        markdown = options.flag("gimp_options_markdown", false);
        if (!markdown) dim = options.integer("gimp_dim", 2);
      } catch (const gimp::input::OptionsReadError &e) {
        return e.code;
      }
      return PETSC_SUCCESS;
    });
    if (!ierr && markdown) { // the option list of docs/options.md
      PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s", gimp::input::optionsMarkdown().c_str()));
      PetscCall(PetscOptionsClearValue(nullptr, "-gimp_options_markdown"));
      PetscCall(PetscFinalize());
      return 0;
    }
    code = ierr ? 1 : dim == 3 ? runScene<3>() : runScene<2>();
  } catch (const gimp::InputError &e) {
    PetscMPIInt rank = 0;
    MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
    if (rank == 0) std::fprintf(stderr, "gimp: error: %s\n", e.what());
    code = 2;
    // A viewer option PETSc reads at exit (-log_view) that the setup did not reach yet: dropped
    // when it is bad too, or PetscFinalize would end the one line with an error trace.
    for (int tries = 0; tries < 2; ++tries)
      try {
        (void)gimp::checkViewerOptions(PETSC_COMM_WORLD);
        break;
      } catch (const gimp::InputError &) { // (cleared; the first error is the one reported)
      }
  } catch (const std::bad_alloc &) {
    outOfMemory(); // does not return under MPI
    code = 2;
  }
  // An input error is detected on every rank alike; finalize cleanly.
  (void)PetscFinalize();
  return code;
}
