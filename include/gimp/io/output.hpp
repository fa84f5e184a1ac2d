// Run output in the scene's output directory (the contract is docs/output.md): HDF5 particle and
// grid fields with XDMF for ParaView (XY or XYZ geometry), history.csv (time series),
// summary.json, hoop.csv (2D hole measure) and the particle dump. Every method is collective;
// files are written by rank 0 (fields.h5 by every rank through PETSc's HDF5 viewer) and a failure
// to write ends every rank with one InputError line.
#pragma once

#include "gimp/grid/grid.hpp"
#include "gimp/input/scene.hpp"
#include "gimp/io/report.hpp"

#include <cstdio>
#include <string>
#include <vector>

namespace gimp {

/// A field frame written: fields.h5's /particles/step_<step> and /grid/step_<step>.
struct OutputFrame {
  PetscInt step;
  double t;
  long long particles;
};

/// Where a restarted run's output continues: history.csv's bytes and the frames written up to
/// the checkpoint (the same on every rank).
struct OutputResume {
  std::string history;
  std::vector<OutputFrame> frames;
};

/// What the writers of every dimension share: the directory, history.csv, the frames written,
/// and files written whole or not at all.
class OutputFiles {
public:
  OutputFiles(MPI_Comm comm, std::string dir) : comm_(comm), dir_(std::move(dir)) {}
  ~OutputFiles();
  OutputFiles(const OutputFiles &) = delete;
  OutputFiles &operator=(const OutputFiles &) = delete;

  /// The frames written so far (every rank).
  const std::vector<OutputFrame> &frames() const { return frames_; }
  /// history.csv's bytes written so far (rank 0; empty elsewhere).
  PetscErrorCode historyText(std::string &text) const;

protected:
  /// Create the directory and remove every file an earlier run wrote there (a restart keeps its
  /// frames and the checkpoint); check that the dump paths can be written; open history.csv
  /// (with `resume`: rewritten with its bytes).
  PetscErrorCode prepare(const OutputResume *resume, const std::string &particleDump,
                         const std::string &gridDump);
  /// Flushes history.csv on rank 0; a failed write cuts the file back to rowStart (the end of
  /// the last whole row) and every rank learns of it (collective).
  PetscErrorCode flushHistory(long rowStart);
  /// fields.h5 keeps the frames of `keep` it holds (rank 0 looks, every rank learns); without
  /// any, the field files are removed (output_resume.cpp).
  PetscErrorCode keepFrames(const std::vector<OutputFrame> &keep);
  /// Opens dir/name (dir/name.tmp when whole) for writing on rank 0; every rank learns of a
  /// failure (collective).
  PetscErrorCode openOnRoot(const std::string &name, FILE **f, bool whole) const;
  /// Closes it on rank 0, checking every write, and renames name.tmp into place when whole
  /// (a failure leaves the previous version or none, never half a file); collective.
  PetscErrorCode closeOnRoot(const std::string &name, FILE *f, bool whole) const;
  /// Before a frame of `bytes`: room for it in fields.h5 (collective; one line when there is
  /// none); after it (written by every rank): the room given back.
  PetscErrorCode reserveFrame(PetscInt step, long double bytes) const;
  void releaseFrame() const;

  MPI_Comm comm_;
  PetscMPIInt rank_ = 0;
  std::string dir_;
  FILE *history_ = nullptr;
  std::vector<OutputFrame> frames_;
};

template <int D> class Output : public OutputFiles {
public:
  /// moves: the run's moves of level boxes that follow a point (RunMeasures::regrids), from which
  /// the grid XDMF places each frame's levels where they were when it was written.
  Output(MPI_Comm comm, const Scene<D> &sc, const Grid<D> &grid,
         const std::vector<RegridRecord> &moves)
      : OutputFiles(comm, sc.outputDir), sc_(sc), grid_(grid), moves_(moves) {}

  /// Prepare the directory and start history.csv (its header); with `resume` (a restart):
  /// history.csv is rewritten with its bytes, and fields.h5 keeps the resumed frames that it
  /// holds and drops every other.
  PetscErrorCode open(const OutputResume *resume = nullptr);
  PetscErrorCode writeHistory(const HistoryRow &row);
  /// Particle fields of the swarm and each level's nodal velocity and mass (global Vecs).
  PetscErrorCode writeFields(PetscInt step, double t, DM sw, Vec velocity, Vec mass);
  PetscErrorCode writeSummary(const SummaryReport &r);
  /// The hole measure's hoop stress (hoop.csv, hoop_fit.csv).
  PetscErrorCode writeHoop(const HoleMeasure &h);

private:
  /// Bytes to reserve for one frame of fields.h5 (an upper bound).
  long double frameBytes(PetscInt64 particles) const;
  /// One HDF5 frame; an error code (no stack printed) when a write fails.
  PetscErrorCode writeFrame(PetscInt step, double t, DM sw, Vec velocity, Vec mass);
  PetscErrorCode writeParticleFrame(PetscViewer v, const std::string &g, double t, DM sw) const;
  PetscErrorCode writeGridFrame(PetscViewer v, const std::string &g, Vec velocity, Vec mass) const;
  PetscErrorCode writeXdmf() const;
  void writeParticleXdmf(FILE *fp) const;
  void writeGridXdmf(FILE *fg) const;
  // summary.json in three parts (rank 0): the run and its grid; energies, reactions and probes;
  // measures and crack tips.
  void summaryRun(FILE *f, const SummaryReport &r) const;
  void summaryState(FILE *f, const SummaryReport &r) const;
  void summaryMeasures(FILE *f, const SummaryReport &r) const;

  /// Level k's low corner when the frame of `step` was written (before any move after that
  /// step's report).
  const double *levelOrigin(size_t k, PetscInt step) const;

  const Scene<D> &sc_;
  const Grid<D> &grid_;
  const std::vector<RegridRecord> &moves_;
};

/// The particles sorted by id as CSV (collective): id, x, y[, z], vx, vy[, vz], the stress
/// components (stressComponents<D>), V, lx, ly[, lz]. A failed write removes the partial file
/// and ends every rank with one line.
template <int D> PetscErrorCode writeParticleDump(MPI_Comm comm, DM sw, const std::string &file);

/// Rows of `cols` values per particle (this rank's, in `loc`; the id in column 0) as CSV with the
/// header line, gathered on rank 0 and sorted by id (collective; the failures as above).
PetscErrorCode writeRowsById(MPI_Comm comm, const std::string &file, const char *header, int cols,
                             const std::vector<double> &loc);

} // namespace gimp
