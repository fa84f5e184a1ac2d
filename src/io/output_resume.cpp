// A restarted run's output: history.csv's bytes for the checkpoint, and fields.h5 cut back to
// the frames the checkpoint had written (later frames of the interrupted run are dropped, so
// fields.h5 and the XDMF files list what the uninterrupted run would have).
#include "gimp/io/checked.hpp"
#include "gimp/io/output.hpp"

#include <hdf5.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>

namespace gimp {

namespace {

herr_t collectName(hid_t, const char *name, const H5L_info_t *, void *data) {
  static_cast<std::vector<std::string> *>(data)->push_back(name);
  return 0;
}

/// Delete every child of `group` in file f whose name is not in `keep`.
void dropChildren(hid_t f, const char *group, const std::set<std::string> &keep) {
  if (H5Lexists(f, group, H5P_DEFAULT) <= 0) return;
  const hid_t g = H5Gopen2(f, group, H5P_DEFAULT);
  if (g < 0) return;
  std::vector<std::string> names;
  H5Literate(g, H5_INDEX_NAME, H5_ITER_NATIVE, nullptr, collectName, &names);
  for (const std::string &n : names)
    if (!keep.count(n)) H5Ldelete(g, n.c_str(), H5P_DEFAULT);
  H5Gclose(g);
}

/// Whether /particles/<g> is the frame `fr` (its time and particle count), not a frame of the same
/// step written by another run into the same directory.
bool sameFrame(hid_t f, const std::string &g, const OutputFrame &fr) {
  const hid_t grp = H5Gopen2(f, ("/particles/" + g).c_str(), H5P_DEFAULT);
  if (grp < 0) return false;
  double t = NAN;
  bool same = false;
  if (H5Aexists(grp, "time") > 0) {
    const hid_t a = H5Aopen(grp, "time", H5P_DEFAULT);
    if (a >= 0 && H5Aread(a, H5T_NATIVE_DOUBLE, &t) >= 0 && t == fr.t) {
      const hid_t d = H5Dopen2(grp, "x", H5P_DEFAULT);
      if (d >= 0) {
        const hid_t sp = H5Dget_space(d);
        hsize_t dims[2] = {0, 0};
        same = sp >= 0 && H5Sget_simple_extent_ndims(sp) >= 1 &&
               H5Sget_simple_extent_dims(sp, dims, nullptr) >= 1 &&
               static_cast<long long>(dims[0]) == fr.particles;
        if (sp >= 0) H5Sclose(sp);
        H5Dclose(d);
      }
    }
    if (a >= 0) H5Aclose(a);
  }
  H5Gclose(grp);
  return same;
}

/// The frames of `keep` that fields.h5 holds whole (both groups, the same time and particle
/// count); every other frame group is deleted. Rank 0 only; a file HDF5 cannot open counts as
/// holding none.
std::vector<OutputFrame> pruneFields(const std::string &file,
                                     const std::vector<OutputFrame> &keep) {
  std::vector<OutputFrame> kept;
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) return kept;
  {
    const QuietErrors quiet(false); // a damaged file is not an error here
    const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    if (f >= 0) {
      std::set<std::string> names;
      for (const OutputFrame &fr : keep) {
        const std::string g = frameGroup(fr.step);
        if (H5Lexists(f, "/particles", H5P_DEFAULT) > 0 && H5Lexists(f, "/grid", H5P_DEFAULT) > 0 &&
            H5Lexists(f, ("/particles/" + g).c_str(), H5P_DEFAULT) > 0 &&
            H5Lexists(f, ("/grid/" + g).c_str(), H5P_DEFAULT) > 0 && sameFrame(f, g, fr)) {
          kept.push_back(fr);
          names.insert(g);
        }
      }
      dropChildren(f, "/particles", names);
      dropChildren(f, "/grid", names);
      H5Fclose(f);
    }
  }
  if (kept.empty()) std::filesystem::remove(file, ec);
  return kept;
}

} // namespace

PetscErrorCode OutputFiles::historyText(std::string &text) const {
  text.clear();
  std::string error;
  if (rank_ == 0) {
    std::fflush(history_);
    const long end = std::ftell(history_);
    FILE *f = std::fopen((dir_ + "/history.csv").c_str(), "rb");
    bool ok = f && end >= 0;
    if (ok) {
      text.resize(static_cast<size_t>(end));
      ok = std::fread(text.data(), 1, text.size(), f) == text.size();
    }
    if (f) std::fclose(f);
    if (!ok) error = "option -gimp_output_dir " + dir_ + ": cannot read back history.csv there";
  }
  PetscCall(agree(comm_, error));
  return PETSC_SUCCESS;
}

PetscErrorCode OutputFiles::keepFrames(const std::vector<OutputFrame> &keep) {
  std::vector<double> kept; // step, t, particles of each frame kept (rank 0, then every rank)
  if (rank_ == 0)
    for (const OutputFrame &fr : pruneFields(dir_ + "/fields.h5", keep))
      kept.insert(kept.end(),
                  {static_cast<double>(fr.step), fr.t, static_cast<double>(fr.particles)});
  long long n = static_cast<long long>(kept.size());
  PetscCallMPI(MPI_Bcast(&n, 1, MPI_LONG_LONG, 0, comm_));
  kept.resize(static_cast<size_t>(n));
  if (n) PetscCallMPI(MPI_Bcast(kept.data(), static_cast<int>(n), MPI_DOUBLE, 0, comm_));
  frames_.clear();
  for (size_t q = 0; q < kept.size(); q += 3)
    frames_.push_back(
        {static_cast<PetscInt>(kept[q]), kept[q + 1], static_cast<long long>(kept[q + 2])});
  if (frames_.empty() && rank_ == 0) { // (else the caller lists the frames in the XDMF files)
    std::error_code ec;
    for (const char *name : {"fields.h5", "particles.xmf", "grid.xmf"})
      std::filesystem::remove(dir_ + "/" + name, ec);
  }
  PetscCallMPI(MPI_Barrier(comm_));
  return PETSC_SUCCESS;
}

} // namespace gimp
