// Inspection of a checkpoint before a restart (checkpoint_file.hpp): rank 0 reads every field
// through HDF5 and checks its presence, type, size against the counts the file records and its
// values, so that PETSc's reader (checkpoint.cpp) only ever meets a whole file of this scene.
#include "checkpoint_file.hpp"

#include "gimp/core/errors.hpp"
#include "gimp/input/scene_record.hpp"
#include "gimp/io/checked.hpp"

#include <hdf5.h>

#include <cmath>
#include <cstring>
#include <filesystem>

namespace gimp::ckpt {

std::vector<double> packText(const std::string &text) {
  std::vector<double> packed(1 + (text.size() + 7) / 8, 0.0);
  packed[0] = static_cast<double>(text.size());
  if (!text.empty()) std::memcpy(packed.data() + 1, text.data(), text.size());
  return packed;
}

std::string unpackText(const std::vector<double> &packed) {
  std::string text(static_cast<size_t>(packed.at(0)), '\0');
  if (!text.empty()) std::memcpy(text.data(), packed.data() + 1, text.size());
  return text;
}

namespace {

/// An HDF5 identifier closed when it goes out of scope.
class Handle {
public:
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  Handle(const Handle &) = delete;
  Handle &operator=(const Handle &) = delete;
  hid_t operator*() const { return id_; }
  bool ok() const { return id_ >= 0; }

private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

/// Whether x is a whole number from 0 to 2^53.
bool isCount(double x) {
  return std::isfinite(x) && x >= 0 && x <= 9007199254740992.0 && x == std::floor(x);
}

/// Dataset `path` of f, a float64 dataset of one or two dimensions, into v and dims ("" or why
/// not).
std::string readDataset(hid_t f, const std::string &path, std::vector<double> &v,
                        std::vector<hsize_t> &dims) {
  if (H5Lexists(f, path.c_str(), H5P_DEFAULT) <= 0) return "is missing";
  const Handle d(H5Dopen2(f, path.c_str(), H5P_DEFAULT), H5Dclose);
  if (!d.ok()) return "is not a dataset";
  const Handle t(H5Dget_type(*d), H5Tclose), sp(H5Dget_space(*d), H5Sclose);
  if (!t.ok() || H5Tget_class(*t) != H5T_FLOAT || H5Tget_size(*t) != 8)
    return "is not of type float64";
  const int nd = sp.ok() ? H5Sget_simple_extent_ndims(*sp) : -1;
  if (nd < 1 || nd > 2) return "has " + std::to_string(nd) + " dimensions, not 1 or 2";
  dims.assign(static_cast<size_t>(nd), 0);
  if (H5Sget_simple_extent_dims(*sp, dims.data(), nullptr) < 0) return "has no readable size";
  long double n = 1;
  for (hsize_t x : dims)
    n *= static_cast<long double>(x);
  if (n < 1 || n > 1e10) return "holds " + formatNumber(static_cast<double>(n)) + " values";
  v.assign(static_cast<size_t>(n), 0.0);
  if (H5Dread(*d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0)
    return "cannot be read (a truncated or damaged file)";
  return "";
}

/// Where v holds a value that is not finite, or "".
std::string notFinite(const std::vector<double> &v, size_t from, size_t components,
                      const char *item) {
  for (size_t i = from; i < v.size(); ++i)
    if (!std::isfinite(v[i]))
      return "holds " + formatNumber(v[i]) + " at " + item + " " +
             std::to_string((i - from) / components);
  return "";
}

/// An array [n, values...] (text: [n, bytes, the bytes 8 to a value]) into a, checked.
std::string readArray(hid_t f, const std::string &path, std::vector<double> &a, bool text) {
  std::vector<double> v;
  std::vector<hsize_t> dims;
  std::string why = readDataset(f, path, v, dims);
  if (why.empty() && dims.size() != 1) why = "is not one-dimensional";
  if (why.empty() && (!isCount(v[0]) || v[0] != static_cast<double>(v.size() - 1)))
    why = "records " + formatNumber(v[0]) + " values but holds " + std::to_string(v.size() - 1);
  if (why.empty() && text &&
      (v.size() < 2 || !isCount(v[1]) || std::ceil(v[1] / 8) != static_cast<double>(v.size() - 2)))
    why = "records " + formatNumber(v.size() < 2 ? NAN : v[1]) + " bytes but holds " +
          std::to_string(v.size() < 2 ? 0 : 8 * (v.size() - 2));
  if (why.empty() && !text) why = notFinite(v, 1, 1, "position");
  if (!why.empty()) return "the field " + path + " " + why;
  a.assign(v.begin() + 1, v.end());
  return "";
}

/// The attribute /state/<name> (a float64 scalar) into x.
std::string readScalar(hid_t f, const char *name, double &x) {
  const std::string what = std::string("the attribute /state/") + name + " ";
  if (H5Aexists_by_name(f, "/state", name, H5P_DEFAULT) <= 0) return what + "is missing";
  const Handle a(H5Aopen_by_name(f, "/state", name, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (!a.ok()) return what + "cannot be opened";
  const Handle t(H5Aget_type(*a), H5Tclose), sp(H5Aget_space(*a), H5Sclose);
  if (!t.ok() || H5Tget_class(*t) != H5T_FLOAT || H5Tget_size(*t) != 8)
    return what + "is not of type float64";
  if (!sp.ok() || H5Sget_simple_extent_npoints(*sp) != 1) return what + "is not one value";
  if (H5Aread(*a, H5T_NATIVE_DOUBLE, &x) < 0) return what + "cannot be read";
  return "";
}

/// Why the value x of scalar q is impossible, or "".
std::string scalarWhy(size_t q, double x) {
  const std::string name = kScalars[q];
  const std::string is = "the attribute /state/" + name + " is " + formatNumber(x);
  if (std::isnan(x) &&
      (name == "separation_strain" || name == "dt_critical" || name == "strain_before"))
    return "";
  if (!std::isfinite(x)) return is + ", not a finite number";
  for (const char *count : {"step", "ranks", "particles", "migrated", "rest_rows", "at_rest"})
    if (name == count && !isCount(x)) return is + ", not a count";
  if ((name == "ranks" || name == "particles" || name == "dt" || name == "mean_particle_mass") &&
      !(x > 0))
    return is + ", not > 0";
  if (name == "time" && x < 0) return is + ", not >= 0";
  if (name == "at_rest" && x > 1) return is + ", not 0 or 1";
  return "";
}

/// The particle fields the scene needs: present, (N, components), finite (integers whole).
template <int D>
std::string particlesWhy(hid_t f, const OptionalFields &need, double particles, double ranks) {
  std::vector<double> sizes;
  std::string why = readArray(f, "/particles/local_sizes", sizes, false);
  if (!why.empty()) return why;
  double sum = 0;
  for (double x : sizes)
    if (!isCount(x))
      return "the field /particles/local_sizes holds " + formatNumber(x);
    else
      sum += x;
  if (static_cast<double>(sizes.size()) != ranks || sum != particles)
    return "the field /particles/local_sizes holds " + std::to_string(sizes.size()) +
           " ranks' counts summing to " + formatNumber(sum) + ", the file records " +
           formatNumber(ranks) + " ranks and " + formatNumber(particles) + " particles";
  for (const FieldSpec<D> &fs : particleFields<D>()) {
    if (!need.has(fs.need)) continue;
    const std::string path = "/particles/" + std::string(fs.name);
    std::vector<double> v;
    std::vector<hsize_t> dims;
    why = readDataset(f, path, v, dims);
    const std::vector<hsize_t> want =
        fs.components == 1 ? std::vector<hsize_t>{static_cast<hsize_t>(particles)}
                           : std::vector<hsize_t>{static_cast<hsize_t>(particles),
                                                  static_cast<hsize_t>(fs.components)};
    if (why.empty() && dims != want)
      why = "holds " + std::to_string(v.size()) + " values, not " + formatNumber(particles) +
            " particles x " + std::to_string(fs.components);
    if (why.empty()) why = notFinite(v, 0, static_cast<size_t>(fs.components), "particle");
    const bool positive = !std::strcmp(fs.name, "m") || !std::strcmp(fs.name, "V") ||
                          !std::strcmp(fs.name, "V0"); // masses and volumes
    for (size_t i = 0; why.empty() && positive && i < v.size(); ++i)
      if (!(v[i] > 0))
        why = "holds " + formatNumber(v[i]) + ", not > 0, at particle " + std::to_string(i);
    for (size_t i = 0; why.empty() && fs.type != PETSC_REAL && i < v.size(); ++i)
      if (v[i] != std::floor(v[i]))
        why = "holds " + formatNumber(v[i]) + ", not an integer, at particle " +
              std::to_string(i / static_cast<size_t>(fs.components));
    if (!why.empty()) return "the field " + path + " " + why;
  }
  return "";
}

/// Every field of a checkpoint of this layout and scene ("" or why it is damaged).
template <int D> std::string damage(hid_t f, const OptionalFields &need) {
  double sv[kNScalars] = {};
  for (size_t q = 1; q < kNScalars; ++q) {
    std::string why = readScalar(f, kScalars[q], sv[q]);
    if (why.empty()) why = scalarWhy(q, sv[q]);
    if (!why.empty()) return why;
  }
  std::vector<double> a;
  for (const char *name : {"max_gaps", "reactions", "gaps", "frames", "history"}) {
    const std::string why =
        readArray(f, "/state/" + std::string(name), a, std::strcmp(name, "history") == 0);
    if (!why.empty()) return why;
    if (std::strcmp(name, "frames") == 0 && a.size() % 3 != 0)
      return "the field /state/frames holds " + std::to_string(a.size()) +
             " values, not 3 per frame";
  }
  std::string why = readArray(f, "/state/grid", a, false);
  if (why.empty() && (a.empty() || a.size() % (1 + 3 * D) != 0))
    why = "the field /state/grid holds " + std::to_string(a.size()) + " values, not " +
          std::to_string(1 + 3 * D) + " per level of a " + std::to_string(D) + "D grid";
  return why.empty() ? particlesWhy<D>(f, need, sv[5], sv[4]) : why;
}

} // namespace

template <int D>
std::string checkpointRefusal(const std::string &file, const OptionalFields &need) {
  const QuietErrors quiet(false);
  const std::string pre = "option -gimp_restart " + file + ": ";
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec) || H5Fis_hdf5(file.c_str()) <= 0)
    return pre + "not a gimp checkpoint (no HDF5 file there)";
  const Handle f(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!f.ok()) return pre + "the HDF5 file cannot be opened (truncated or damaged)";
  if (H5Lexists(*f, "/state", H5P_DEFAULT) <= 0 || H5Lexists(*f, "/particles", H5P_DEFAULT) <= 0)
    return pre + "not a gimp checkpoint (no /state and /particles in the file)";
  double format = 0;
  std::string why = readScalar(*f, kScalars[0], format);
  if (!why.empty()) return pre + why + " (a damaged checkpoint)";
  if (format != kFormat)
    return pre + "its layout version " + formatNumber(format) + " is not " + formatNumber(kFormat) +
           " (written by another version of gimp)";
  std::vector<double> scene;
  why = readArray(*f, "/state/scene", scene, true);
  if (!why.empty()) return pre + why + " (a damaged checkpoint)";
  why = input::sceneDifference(unpackText(scene), input::sceneRecord(), file);
  if (!why.empty()) return why;
  why = damage<D>(*f, need);
  return why.empty() ? "" : pre + why + " (a damaged checkpoint)";
}

template std::string checkpointRefusal<2>(const std::string &, const OptionalFields &);
template std::string checkpointRefusal<3>(const std::string &, const OptionalFields &);

} // namespace gimp::ckpt
