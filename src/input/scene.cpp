// readScene<D>: the scene from the options database, each option read by its declaration
// (input/options.hpp). The run, the method, the material, the grid's domain and levels here; the
// bodies per dimension (bodies_plane.cpp, bodies_solid.cpp), loads (loads.cpp) and cracks
// (scene_cracks.cpp) in their files.
#include "gimp/input/scene.hpp"

#include "scene_options.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <regex>

namespace gimp::input {

namespace {

/// A scene name names the default output directory output/<name>: a plain file name.
bool plainFileName(const std::string &s) {
  if (s.empty() || s == "." || s == "..") return false;
  for (const char c : s)
    if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' ||
          c == '_' || c == '.'))
      return false;
  return true;
}

/// Outputs, monitors, measures.
template <int D> void readOutputs(const Options &o, Scene<D> &sc) {
  sc.name = o.word("gimp_scene", "scene");
  if (!o.help() && !plainFileName(sc.name))
    Options::bad("gimp_scene", sc.name,
                 "a scene name is a plain file name: letters, digits, '-', '_' and '.', not '.' "
                 "or '..' (it names the output directory output/<scene>)");
  sc.outputDir = o.word("gimp_output_dir", "output/" + sc.name);
  sc.outputInterval = static_cast<int>(o.integer("gimp_output_interval", 0));
  sc.historyInterval = static_cast<int>(o.integer("gimp_history_interval", 10));
  sc.monitorInterval = static_cast<int>(o.integer("gimp_monitor_interval", 0));
  sc.sortInterval = static_cast<int>(o.integer("gimp_sort_interval", 50));
  sc.checkpointInterval =
      static_cast<int>(std::min<PetscInt>(o.integer("gimp_checkpoint_interval", 0), INT_MAX));
  sc.restart = o.word("gimp_restart", "");
  sc.particleDump = o.word("gimp_particle_dump", "");
  sc.gridDump = o.word("gimp_grid_dump", "");
  if (!o.help() && !sc.gridDump.empty() && sc.gridDump == sc.particleDump)
    Options::bad("gimp_grid_dump", sc.gridDump,
                 "is the -gimp_particle_dump file too: give two files");
  sc.memoryLimit = o.real("gimp_memory_limit", 0.0);
  sc.mms = o.choice("gimp_mms", "none") == "skb1d" ? Mms::AxialWave : Mms::None;
  sc.mmsAmplitude = o.real("gimp_mms_amplitude", sc.mmsAmplitude);
  o.needs(sc.mms != Mms::None, "gimp_mms_amplitude", "-gimp_mms skb1d");
  sc.lanes = o.flag("gimp_lanes", true);
  sc.balance = o.flag("gimp_balance", true);
  readHoleMeasure(o, sc);
}

/// The enum value whose option name (names, in the enum's order) is v; o.choice has checked v.
template <class E, size_t N> E fromName(const std::string &v, const char *const (&names)[N]) {
  for (size_t i = 0; i < N; ++i)
    if (v == names[i]) return static_cast<E>(i);
  return static_cast<E>(0);
}

/// The update scheme, the transfer and the domain tracking.
template <int D> void readScheme(const Options &o, Scene<D> &sc) {
  sc.update = fromName<Update>(o.choice("gimp_update", "musl"), kUpdateNames);
  const std::string transfer = o.choice("gimp_transfer", "apic");
  sc.transfer = fromName<Transfer>(transfer, kTransferNames);
  bool flipGiven = false, cutoffGiven = false;
  sc.flip = o.real("gimp_flip", 1.0, &flipGiven);
  if (!o.help() && flipGiven && sc.transfer != Transfer::Flip)
    Options::bad("gimp_flip", formatNumber(sc.flip),
                 "blends FLIP and PIC only with -gimp_transfer flip, not " + transfer);
  sc.xpicOrder = static_cast<int>(o.integer("gimp_xpic_order", 2));
  sc.tracking = fromName<Tracking>(o.choice("gimp_tracking", "cpdi2"), kTrackingNames);
  sc.cornerSize = o.real("gimp_corner_size", sc.cornerSize);
  o.needs(sc.tracking == Tracking::Corners, "gimp_corner_size", "-gimp_tracking corners");
  sc.separationThreshold = o.real("gimp_separation_threshold", 0.05);
  sc.halfStepStart = o.flag("gimp_half_step_start", true);
  sc.cutCells = o.flag("gimp_cut_cells", true);
  sc.damping = o.real("gimp_damping", 0.0);
  sc.massCutoff = o.real("gimp_mass_cutoff", 1e-14, &cutoffGiven);
  if (!cutoffGiven) sc.massCutoff = MethodOptions::defaultMassCutoff(sc.transfer);
  sc.cfl = o.real("gimp_cfl", sc.cfl);
}

/// The rest criterion, the stability check and the multi-rate step.
template <int D> void readRunControl(const Options &o, Scene<D> &sc) {
  bool staticTime = false;
  sc.staticTol = o.real("gimp_static_tol", 0.0);
  sc.staticTime = o.real("gimp_static_min_time", 0.0, &staticTime);
  sc.stabilityCheck = o.flag("gimp_stability_check", false);
#ifndef GIMP_HAVE_SLEPC
  if (!o.help() && sc.stabilityCheck)
    Options::bad("gimp_stability_check", "true",
                 "needs gimp built with SLEPc (install SLEPc and reconfigure); use false");
#endif
  sc.stabilityInterval =
      static_cast<int>(std::min<PetscInt>(o.integer("gimp_stability_interval", 0), INT_MAX));
  sc.allowUnstableDt = o.flag("gimp_allow_unstable_dt", false);
  o.needs(sc.stabilityCheck, "gimp_stability_interval", "-gimp_stability_check");
  o.needs(sc.stabilityCheck, "gimp_allow_unstable_dt", "-gimp_stability_check");
  sc.multirate = o.flag("gimp_multirate", false);
  sc.multirateNodeRule = o.choice("gimp_multirate_forces", "impulse") == "node";
  o.needs(sc.multirate, "gimp_multirate_forces", "-gimp_multirate true");
  if (sc.multirate && !o.given("gimp_tracking")) sc.tracking = Tracking::Stretch;
  if (!o.help() && sc.multirate && sc.stabilityInterval > 0)
    Options::bad("gimp_stability_interval", std::to_string(sc.stabilityInterval),
                 "re-checks the single-rate step, not -gimp_multirate's; use 0 with "
                 "-gimp_multirate");
  // (A warning, not an error: a file that includes another may turn its rest criterion off.)
  if (!o.help() && staticTime && sc.staticTol == 0)
    PetscCallAbort(PETSC_COMM_WORLD,
                   PetscPrintf(PETSC_COMM_WORLD,
                               "gimp: warning: -gimp_static_min_time %s has no effect: the rest "
                               "criterion is off (-gimp_static_tol 0)\n",
                               formatNumber(sc.staticTime).c_str()));
}

/// The grid domain: as given, or the bodies' bounding box padded by -gimp_pad cells, a whole
/// number of cells along each axis, at least two.
template <int D> void setDomain(const Options &o, Scene<D> &sc) {
  const std::vector<double> given = o.reals("gimp_domain");
  sc.pad = o.integer("gimp_pad", 2);
  sc.domainGiven = !given.empty();
  if (o.help()) return;
  static const char *const axes[] = {"x", "y", "z"};
  BoxOf<D> &dom = sc.domain;
  if (sc.domainGiven) {
    std::copy(given.begin(), given.end(), dom.begin());
    for (int a = 0; a < D; ++a)
      if (!(dom[D + a] > dom[a]))
        Options::bad("gimp_domain", fmtList(dom.data(), 2 * D),
                     std::string("needs ") + axes[a] + "1 > " + axes[a] + "0");
  } else {
    domainAroundBodies(sc);
  }
  for (int a = 0; a < D; ++a) {
    const double n = (dom[D + a] - dom[a]) / sc.h;
    if (std::fabs(n - std::round(n)) > 1e-6 * std::max(1.0, n))
      Options::bad("gimp_domain", fmtList(dom.data(), 2 * D),
                   std::string("its extent in ") + axes[a] + " (" +
                       formatNumber(dom[D + a] - dom[a]) +
                       " m) is not a whole number of cells of -gimp_h " + formatNumber(sc.h));
    if (std::round(n) < 2)
      Options::bad("gimp_domain", fmtList(dom.data(), 2 * D),
                   "needs at least 2 cells of -gimp_h in each direction");
  }
}

/// -gimp_levelK_follow and _follow_margin: none, crackC_tipT, crackC_front or probeN (the crack,
/// tip and probe checked against the scene in validate.cpp), the margin within half the box's
/// smallest side.
template <int D> LevelFollow readFollow(const Options &o, size_t k, const BoxOf<D> &box) {
  const std::string p = "gimp_level" + std::to_string(k) + "_";
  const std::string what = o.word(p + "follow", "none");
  bool marginGiven = false;
  const double margin = o.real(p + "follow_margin", 0.0, &marginGiven);
  LevelFollow f;
  if (o.help()) return f;
  const std::string valid = "none, crackC_tipT (crack C's tip T: 0 its first point, 1 its last), "
                            "crackC_front (the centre of 3D crack C's front) or probeN (the "
                            "particle of probe N)";
  static const std::regex tipForm("crack([0-9]{1,4})_tip([01])"), probeForm("probe([0-9]{1,4})"),
      frontForm("crack([0-9]{1,4})_front");
  std::smatch m;
  if (what == "none") {
    f.kind = LevelFollow::Kind::None;
  } else if (std::regex_match(what, m, tipForm)) {
    f = {LevelFollow::Kind::CrackTip, std::stoi(m[1]), std::stoi(m[2]), 0};
  } else if (std::regex_match(what, m, frontForm)) {
    f = {LevelFollow::Kind::CrackFront, std::stoi(m[1]), 0, 0};
  } else if (std::regex_match(what, m, probeForm)) {
    f = {LevelFollow::Kind::Probe, std::stoi(m[1]), 0, 0};
  } else {
    Options::bad(p + "follow", what, valid);
  }
  double side = 1e300;
  for (int d = 0; d < D; ++d)
    side = std::min(side, box[D + d] - box[d]);
  f.margin = marginGiven ? margin : 0.25 * side;
  if (marginGiven && f.kind == LevelFollow::Kind::None)
    Options::bad(p + "follow_margin", formatNumber(margin),
                 "it acts with -" + p +
                     "follow (a crack tip or front, or a probe), which is not given");
  if (marginGiven && !(margin < 0.5 * side))
    Options::bad(p + "follow_margin", formatNumber(margin),
                 "a distance > 0 below half the box's smallest side, " + formatNumber(0.5 * side) +
                     " m");
  return f;
}

/// The levels: level 0 the domain, level K > 0 a box and a ratio to its parent.
template <int D> void readLevels(const Options &o, Scene<D> &sc) {
  const PetscInt n = o.integer("gimp_levels", 1);
  sc.levels.assign(1, LevelBox<D>{sc.domain, 1});
  for (PetscInt k = 1; k < (o.help() ? 2 : n); ++k) {
    const std::string p = "gimp_level" + std::to_string(k) + "_";
    const std::vector<double> box = o.reals(p + "box", !o.help());
    const double ratio = o.real(p + "ratio", 2.0);
    if (o.help()) continue;
    LevelBox<D> L;
    std::copy(box.begin(), box.end(), L.box.begin());
    L.ratio = static_cast<int>(ratio);
    sc.levels.push_back(L);
  }
  sc.follow.assign(sc.levels.size(), LevelFollow{});
  for (size_t k = 1; k < (o.help() ? 2 : sc.levels.size()); ++k)
    sc.follow[o.help() ? 0 : k] = readFollow<D>(o, k, o.help() ? BoxOf<D>{} : sc.levels[k].box);
  bool mergeGiven = false;
  sc.followMerge = o.flag("gimp_follow_merge", sc.followMerge, &mergeGiven);
  if (mergeGiven && !o.help() && !sc.follows())
    Options::bad("gimp_follow_merge", sc.followMerge ? "true" : "false",
                 "it acts with -gimp_levelK_follow, which no level gives");
}

/// The manufactured solution's model: one neo-Hookean material with nu = 0.
template <int D> void checkModel(const Scene<D> &sc) {
  if (sc.mms == Mms::AxialWave &&
      (sc.material.model != MaterialModel::NeoHookean || sc.material.nu != 0 || !sc.oneMaterial))
    Options::bad("gimp_mms", "skb1d",
                 "the 1D manufactured solution needs -gimp_material neohookean and -gimp_nu 0 "
                 "(one material)");
}

template <int D> void readSceneOptions(MPI_Comm comm, Scene<D> &sc) {
  PetscBool help = PETSC_FALSE;
  (void)PetscOptionsHasHelp(nullptr, &help);
  sc.help = help;
  if (!sc.help) refuseOtherDimension(D);
  const Options o(comm, D, sc.help);
  // (main chose the solver by it; read here too, so that it counts as used)
  if (o.integer("gimp_dim", 2) != D && !o.help())
    Options::bad("gimp_dim", std::to_string(o.integer("gimp_dim", 2)),
                 "the scene is read by the solver of dimension " + std::to_string(D));
  readOutputs(o, sc);
  bool hGiven = false;
  sc.h = o.real("gimp_h", 0.0, &hGiven);
  readScheme(o, sc);
  readRunControl(o, sc);
  readMaterial(o, sc);
  readBodies(o, sc);
  readLoads(o, sc);
  if (!o.help() && !hGiven)
    Options::bad("gimp_h", "(missing)", "the cell size is required, a value > 0 in m");
  setDomain(o, sc);
  readLevels(o, sc);
  if (!o.help()) {
    checkModel(sc);
    checkBodies(sc);
  }
  readCracks(o, sc);
}

} // namespace

} // namespace gimp::input

namespace gimp {

template <int D> PetscErrorCode readScene(MPI_Comm comm, Scene<D> &sc) {
  try {
    input::readSceneOptions(comm, sc);
  } catch (const input::OptionsReadError &e) {
    return e.code;
  }
  return PETSC_SUCCESS;
}

template PetscErrorCode readScene<2>(MPI_Comm, Scene<2> &);
template PetscErrorCode readScene<3>(MPI_Comm, Scene<3> &);

} // namespace gimp
