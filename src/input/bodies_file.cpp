// Bodies from particle files (-gimp_bodyK_shape file), in both dimensions: the file read on rank
// 0 and received by every rank, the body's box the bounding box of its particles' domains, and
// the check that every particle lies in the grid domain and is no larger than a level-0 cell.
#include "gimp/input/particle_file.hpp"
#include "scene_options.hpp"

#include <algorithm>

namespace gimp::input {

template <int D>
BoxOf<D> readFileBody(const Options &o, const std::string &q, double thickness, std::string &file,
                      ParticleFile<D> &out) {
  if (file.empty()) Options::bad(q + "file", "(missing)", "each body of shape file needs it");
  if (const PetscErrorCode e =
          readParticleFile<D>(o.comm(), "-" + q + "file", file, thickness, out))
    throw OptionsReadError{e};
  BoxOf<D> bb;
  for (int a = 0; a < D; ++a) {
    bb[a] = 1e300;
    bb[D + a] = -1e300;
  }
  for (const FileParticle<D> &f : out.particles)
    for (int a = 0; a < D; ++a) {
      bb[a] = std::min(bb[a], f.x[a] - f.l[a]);
      bb[D + a] = std::max(bb[D + a], f.x[a] + f.l[a]);
    }
  return bb;
}

template <int D> void checkFileParticles(const Scene<D> &sc, size_t k) {
  const std::vector<FileParticle<D>> &ps = sc.bodies[k].fromFile.particles;
  const std::string opt = "gimp_body" + std::to_string(k) + "_file";
  auto list = [](const double *v) {
    std::string out;
    for (int a = 0; a < D; ++a)
      out += (a ? "," : "") + formatNumber(v[a]);
    return out;
  };
  for (size_t i = 0; i < ps.size(); ++i)
    for (int a = 0; a < D; ++a)
      if (ps[i].l[a] > sc.h) // the stencils reach one level-0 cell
        Options::bad(opt, sc.bodies[k].file,
                     "particle " + std::to_string(i) + " (data row " + std::to_string(i + 1) +
                         ") has half-sizes " + list(ps[i].l) +
                         " larger than the coarsest cell -gimp_h " + formatNumber(sc.h));
  for (size_t i = 0; i < ps.size(); ++i)
    for (int a = 0; a < D; ++a)
      if (ps[i].x[a] - ps[i].l[a] < sc.domain[a] || ps[i].x[a] + ps[i].l[a] > sc.domain[D + a])
        Options::bad(opt, sc.bodies[k].file,
                     "particle " + std::to_string(i) + " (data row " + std::to_string(i + 1) +
                         ", at " + list(ps[i].x) + ") is not inside the grid domain " +
                         fmtList(sc.domain.data(), 2 * D));
}

template BoxOf<2> readFileBody<2>(const Options &, const std::string &, double, std::string &,
                                  ParticleFile<2> &);
template BoxOf<3> readFileBody<3>(const Options &, const std::string &, double, std::string &,
                                  ParticleFile<3> &);
template void checkFileParticles<2>(const Scene<2> &, size_t);
template void checkFileParticles<3>(const Scene<3> &, size_t);

} // namespace gimp::input
