// Run output in the scene's output directory (the contract is docs/output.md): HDF5 particle and
// grid fields with XDMF for ParaView, history.csv (time series), summary.json and hoop.csv.
// Every method is collective; files are written by rank 0 and a failure to write ends every
// rank with one InputError line.
#pragma once

#include "gimp/grid/grid.hpp"
#include "gimp/io/report.hpp"

#include <cstdio>
#include <string>
#include <vector>

namespace gimp {

class Output {
public:
  Output(MPI_Comm comm, const Scene<2> &sc, const Grid<2> &grid)
      : comm_(comm), sc_(sc), grid_(grid) {}
  ~Output();
  Output(const Output &) = delete;
  Output &operator=(const Output &) = delete;

  /// A field frame written: fields.h5's /particles/step_<step> and /grid/step_<step>.
  struct Frame {
    PetscInt step;
    double t;
    long long particles;
  };
  /// Where a restarted run's output continues: history.csv's bytes and the frames written up
  /// to the checkpoint (the same on every rank).
  struct Resume {
    std::string history;
    std::vector<Frame> frames;
  };

  /// Create the directory, remove every file an earlier run wrote there (and its particle
  /// dump), check that the dump paths can be written, start history.csv. With `resume` (a
  /// restart): history.csv is rewritten with its bytes, and fields.h5 keeps the resumed frames
  /// that it holds and drops every other (output_resume.cpp).
  PetscErrorCode open(const Resume *resume = nullptr);
  PetscErrorCode writeHistory(const HistoryRow &row);
  /// Particle fields of the swarm and each level's nodal velocity and mass (global Vecs).
  PetscErrorCode writeFields(PetscInt step, double t, DM sw, Vec velocity, Vec mass);
  PetscErrorCode writeSummary(const SummaryReport &r);
  PetscErrorCode writeHoop(const HoleMeasure &h);
  /// The frames written so far (every rank).
  const std::vector<Frame> &frames() const { return frames_; }
  /// history.csv's bytes written so far (rank 0; empty elsewhere).
  PetscErrorCode historyText(std::string &text) const;

private:
  /// Bytes to reserve for one frame of fields.h5 (an upper bound).
  long double frameBytes(PetscInt64 particles) const;
  /// One HDF5 frame; an error code (no stack printed) when a write fails.
  PetscErrorCode writeFrame(PetscInt step, double t, DM sw, Vec velocity, Vec mass);
  PetscErrorCode writeParticleFrame(PetscViewer v, const std::string &g, double t, DM sw) const;
  PetscErrorCode writeGridFrame(PetscViewer v, const std::string &g, Vec velocity, Vec mass) const;
  /// Flushes history.csv on rank 0; a failed write cuts the file back to rowStart (the end of
  /// the last whole row) and every rank learns of it (collective).
  PetscErrorCode flushHistory(long rowStart);
  std::string checkDumpPaths() const;
  /// fields.h5 keeps the frames of `keep` it holds (rank 0 looks, every rank learns), the XDMF
  /// files list them (output_resume.cpp).
  PetscErrorCode resumeFrames(const std::vector<Frame> &keep);
  PetscErrorCode writeXdmf() const;
  // summary.json in three parts (rank 0): the run and its grid; energies, reactions and probes;
  // measures and crack tips.
  void summaryRun(FILE *f, const SummaryReport &r) const;
  void summaryState(FILE *f, const SummaryReport &r) const;
  void summaryMeasures(FILE *f, const SummaryReport &r) const;
  PetscErrorCode writeParticleXdmf(FILE *fp) const;
  PetscErrorCode writeGridXdmf(FILE *fg) const;
  /// Opens dir/name (dir/name.tmp when whole) for writing on rank 0; every rank learns of a
  /// failure (collective).
  PetscErrorCode openOnRoot(const std::string &name, FILE **f, bool whole) const;
  /// Closes it on rank 0, checking every write, and renames name.tmp into place when whole
  /// (a failure leaves the previous version or none, never half a file); collective.
  PetscErrorCode closeOnRoot(const std::string &name, FILE *f, bool whole) const;

  MPI_Comm comm_;
  const Scene<2> &sc_;
  const Grid<2> &grid_;
  PetscMPIInt rank_ = 0;
  std::string dir_;
  FILE *history_ = nullptr;
  std::vector<Frame> frames_;
};

/// The particles sorted by id as CSV id,x,y,vx,vy,sxx,syy,sxy,szz,V,lx,ly (collective);
/// a failed write removes the partial file and ends every rank with one line.
PetscErrorCode writeParticleDump(MPI_Comm comm, DM sw, const std::string &file);

/// Rows of `cols` values per particle (this rank's, in `loc`; the id in column 0) as CSV with the
/// header line, gathered on rank 0 and sorted by id (collective; the failures as above).
PetscErrorCode writeRowsById(MPI_Comm comm, const std::string &file, const char *header, int cols,
                             const std::vector<double> &loc);

} // namespace gimp
