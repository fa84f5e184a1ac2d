// readScene<2>: the 2D scene's run options, the domain, and the parts (scene_parts.cpp).
#include "gimp/input/scene.hpp"

#include "scene_options.hpp"

#include <algorithm>
#include <climits>
#include <cmath>

namespace gimp {

namespace input {

std::string fmtList(const double *v, PetscInt n) {
  std::string r;
  for (PetscInt i = 0; i < n; ++i)
    r += (i ? "," : "") + formatNumber(v[i]);
  return r;
}

[[noreturn]] void bad(const std::string &opt, const std::string &value, const std::string &valid) {
  throw InputError("option -" + opt + " " + value + ": " + valid);
}

void checkRunIntervals(int output, int history, int monitor, int sort) {
  if (output < 0) bad("gimp_output_interval", std::to_string(output), "must be >= 0");
  if (history < 1) bad("gimp_history_interval", std::to_string(history), "must be >= 1");
  if (monitor < 0) bad("gimp_monitor_interval", std::to_string(monitor), "must be >= 0");
  if (sort < 0) bad("gimp_sort_interval", std::to_string(sort), "must be >= 0");
}

bool isPerfectSquare(int n) {
  const int r = static_cast<int>(std::lround(std::sqrt(static_cast<double>(n))));
  return n > 0 && r * r == n;
}

/// PETSc's EList stops with a trace on an unknown value; check it first and say it in one line.
PetscErrorCode checkChoice(const std::string &opt, const char *const *list, int n) {
  char buf[256];
  PetscBool set = PETSC_FALSE;
  PetscCall(PetscOptionsGetString(nullptr, nullptr, opt.c_str(), buf, sizeof(buf), &set));
  if (!set) return PETSC_SUCCESS;
  std::string valid;
  for (int i = 0; i < n; ++i) {
    if (std::string(buf) == list[i]) return PETSC_SUCCESS;
    valid += (i ? ", " : "") + std::string(list[i]);
  }
  bad(opt.substr(1), buf, "must be one of " + valid);
}

} // namespace input

using input::bad;
using input::checkChoice;
using input::fmtList;
using input::readBodies;
using input::readCracks;
using input::readLevels;
using input::readLoads;
using input::readMaterial;

namespace {

/// Options read by readScene itself, before they are checked.
struct RunOptions {
  char name[256] = "scene", outdir[PETSC_MAX_PATH_LEN] = "", pdump[PETSC_MAX_PATH_LEN] = "",
       gdump[PETSC_MAX_PATH_LEN] = "", restart[PETSC_MAX_PATH_LEN] = "";
  PetscReal dom[5] = {0, 0, 0, 0, 0}, hm[4] = {0, 0, 0, 0}; // one spare: extra values are seen
  PetscInt ndom = 5, nhm = 4, pad = 2, update = 2, tracking = 2, mms = 0, stabilityInterval = 0;
  PetscInt transfer = 1, xpicOrder = 2;
  PetscBool setDom = PETSC_FALSE, setH = PETSC_FALSE, setFlip = PETSC_FALSE, setHm = PETSC_FALSE,
            setCutoff = PETSC_FALSE, setHoleLoad = PETSC_FALSE, setStaticTime = PETSC_FALSE;
};

const char *const kUpdates[] = {"usf", "usl", "musl"};
const char *const kTransfers[] = {"flip", "apic", "xpic"};
const char *const kTrackings[] = {"none", "strain", "stretch", "corners", "cpdi", "cpdi2"};
const char *const kMms[] = {"none", "skb1d"};
const char *const kRateForces[] = {"impulse", "node"};

/// Outputs, monitors and measures.
PetscErrorCode readOutputOptions(MPI_Comm comm, Scene<2> &sc, RunOptions &o) {
  char *name = o.name, *outdir = o.outdir, *pdump = o.pdump, *gdump = o.gdump;
  PetscReal *hm = o.hm;
  PetscInt &nhm = o.nhm, &mms = o.mms;
  PetscBool &setHm = o.setHm;
  const char *const *mmss = kMms;
  PetscCall(checkChoice("-gimp_mms", kMms, 2));
  PetscOptionsBegin(comm, nullptr, "gimp scene: outputs and measures", "gimp");
  PetscCall(PetscOptionsString("-gimp_scene", "Scene name (output/<name> by default)",
                               "docs/options.md", name, name, sizeof(o.name), nullptr));
  PetscCall(PetscOptionsString("-gimp_output_dir", "Output directory (default output/<scene>)",
                               "docs/options.md", outdir, outdir, sizeof(o.outdir), nullptr));
  PetscCall(PetscOptionsInt("-gimp_output_interval",
                            "Steps between HDF5 field outputs (0: initial and final only)",
                            "docs/options.md", sc.outputInterval, &sc.outputInterval, nullptr));
  PetscCall(PetscOptionsInt("-gimp_history_interval", "Steps between rows of history.csv",
                            "docs/options.md", sc.historyInterval, &sc.historyInterval, nullptr));
  PetscCall(PetscOptionsInt("-gimp_sort_interval",
                            "Steps between orderings of each rank's particles by level-0 cell "
                            "(0: never)",
                            "docs/options.md", sc.sortInterval, &sc.sortInterval, nullptr));
  PetscBool lanes = sc.lanes ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(PetscOptionsBool("-gimp_lanes",
                             "Run the 2D kernels of block particles four at a time (AVX2, where "
                             "the processor has it; bit for bit the same results)",
                             "docs/options.md", lanes, &lanes, nullptr));
  sc.lanes = lanes;
  PetscCall(PetscOptionsInt("-gimp_monitor_interval",
                            "Steps between energy/momentum monitor lines (0: off)",
                            "docs/options.md", sc.monitorInterval, &sc.monitorInterval, nullptr));
  PetscCall(PetscOptionsEList("-gimp_mms", "Manufactured solution: none or skb1d",
                              "docs/options.md", mmss, 2, mmss[0], &mms, nullptr));
  PetscCall(PetscOptionsReal("-gimp_mms_amplitude", "Amplitude A of the manufactured solution [m]",
                             "docs/options.md", sc.mmsAmplitude, &sc.mmsAmplitude, nullptr));
  PetscCall(PetscOptionsRealArray("-gimp_hole_measure",
                                  "Measure the hoop stress around the hole cx,cy,r [m]: "
                                  "summary.json kt and hoop.csv",
                                  "docs/options.md", hm, &nhm, &setHm));
  PetscCall(PetscOptionsReal("-gimp_hole_measure_load",
                             "Remote stress p that normalises the hoop stress (load along x) [Pa]",
                             "docs/options.md", sc.holeLoad, &sc.holeLoad, &o.setHoleLoad));
  PetscCall(PetscOptionsString("-gimp_particle_dump",
                               "Write the final particles as CSV (sorted by id) to this file",
                               "docs/options.md", pdump, pdump, sizeof(o.pdump), nullptr));
  PetscCall(PetscOptionsString("-gimp_grid_dump",
                               "Write the active grid nodes as CSV level,x,y,Lxm,Lxp,Lym,Lyp",
                               "docs/options.md", gdump, gdump, sizeof(o.gdump), nullptr));
  PetscCall(PetscOptionsInt("-gimp_checkpoint_interval",
                            "Steps between checkpoints (checkpoint.h5 in the output directory; "
                            "0: none, but on SIGINT/SIGTERM)",
                            "docs/options.md", sc.checkpointInterval, &sc.checkpointInterval,
                            nullptr));
  PetscCall(PetscOptionsString(
      "-gimp_restart", "Continue from this checkpoint (give the scene's options again)",
      "docs/options.md", o.restart, o.restart, sizeof(o.restart), nullptr));
  PetscOptionsEnd();
  return PETSC_SUCCESS;
}

/// The particle velocity transfer and its parameters.
PetscErrorCode readTransferOptions(MPI_Comm comm, Scene<2> &sc, RunOptions &o) {
  PetscCall(checkChoice("-gimp_transfer", kTransfers, 3));
  PetscOptionsBegin(comm, nullptr, "gimp scene: velocity transfer", "gimp");
  const char *const *transfers = kTransfers;
  PetscCall(PetscOptionsEList("-gimp_transfer",
                              "Particle velocity transfer: flip (FLIP/PIC blend of -gimp_flip), "
                              "apic (affine PIC) or xpic (XPIC(m), m = -gimp_xpic_order)",
                              "docs/options.md", transfers, 3, transfers[o.transfer], &o.transfer,
                              nullptr));
  PetscCall(PetscOptionsReal("-gimp_flip",
                             "FLIP fraction of the particle velocity update with -gimp_transfer "
                             "flip (1: FLIP, 0: PIC)",
                             "docs/options.md", sc.flip, &sc.flip, &o.setFlip));
  PetscCall(PetscOptionsInt("-gimp_xpic_order",
                            "Order m of XPIC(m): m - 1 extra projections filter the particle "
                            "velocity (1: PIC)",
                            "docs/options.md", o.xpicOrder, &o.xpicOrder, nullptr));
  PetscOptionsEnd();
  return PETSC_SUCCESS;
}

/// The grid's cell size and domain, the update scheme and its parameters.
PetscErrorCode readMethodOptions(MPI_Comm comm, Scene<2> &sc, RunOptions &o) {
  PetscReal *dom = o.dom;
  PetscInt &ndom = o.ndom, &pad = o.pad, &update = o.update, &tracking = o.tracking;
  PetscBool &setDom = o.setDom, &setH = o.setH;
  const char *const *updates = kUpdates, *const *trackings = kTrackings;
  PetscCall(checkChoice("-gimp_update", kUpdates, 3));
  PetscCall(checkChoice("-gimp_tracking", kTrackings, 6));
  PetscInt rule = sc.multirateNodeRule ? 1 : 0; // -gimp_multirate_forces
  PetscBool setRule = PETSC_FALSE;
  PetscOptionsBegin(comm, nullptr, "gimp scene: grid and method", "gimp");
  PetscCall(PetscOptionsReal("-gimp_h", "Cell size of the background grid [m]", "docs/options.md",
                             sc.h, &sc.h, &setH));
  PetscCall(
      PetscOptionsRealArray("-gimp_domain",
                            "Grid domain x0,y0,x1,y1 [m] (default: the bodies' bounding box "
                            "padded by -gimp_pad cells)",
                            "docs/options.md", dom, &ndom, &setDom));
  PetscCall(PetscOptionsInt("-gimp_pad",
                            "Cells of padding around the bodies for the default domain",
                            "docs/options.md", pad, &pad, nullptr));
  PetscCall(PetscOptionsReal("-gimp_damping", "Artificial damping coefficient d of Eq. 16 [1/s]",
                             "docs/options.md", sc.damping, &sc.damping, nullptr));
  PetscCall(PetscOptionsEList("-gimp_update", "Update scheme", "docs/options.md", updates, 3,
                              updates[2], &update, nullptr));
  PetscBool half = sc.halfStepStart ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(PetscOptionsBool("-gimp_half_step_start",
                             "Start the leapfrog with a half kick (particle velocities at half "
                             "steps; second order in time)",
                             "docs/options.md", half, &half, nullptr));
  sc.halfStepStart = half;
  PetscBool cutCells = sc.cutCells ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(PetscOptionsBool("-gimp_cut_cells",
                             "Particles whose square a hole cuts take the area inside the body as "
                             "volume and its centroid as position (false: whole squares whose "
                             "centre is in the body)",
                             "docs/options.md", cutCells, &cutCells, nullptr));
  sc.cutCells = cutCells;
  PetscCall(PetscOptionsEList("-gimp_tracking",
                              "Particle domain tracking: none, strain ((1+eps) l0), stretch (F l0) "
                              "corners (the paper's corner tracking), cpdi (parallelogram F r0) or "
                              "cpdi2 (quadrilateral of tracked corners)",
                              "docs/options.md", trackings, 6, trackings[2], &tracking, nullptr));
  PetscCall(PetscOptionsReal("-gimp_corner_size",
                             "Fictitious size of a tracked corner / initial particle size [-]",
                             "docs/options.md", sc.cornerSize, &sc.cornerSize, nullptr));
  PetscCall(PetscOptionsReal("-gimp_separation_threshold",
                             "Gap between particles that started as neighbours, relative to their "
                             "size, above which they count as separated [-]",
                             "docs/options.md", sc.separationThreshold, &sc.separationThreshold,
                             nullptr));
  PetscCall(PetscOptionsReal("-gimp_mass_cutoff",
                             "Nodes lighter than this fraction of the mean particle mass are "
                             "treated as empty (default 1e-14 with APIC, 1e-8 otherwise) [-]",
                             "docs/options.md", sc.massCutoff, &sc.massCutoff, &o.setCutoff));
  PetscCall(PetscOptionsReal("-gimp_static_tol",
                             "Stop at rest: when the kinetic energy falls below this fraction of "
                             "the strain energy at a history row (0: off) [-]",
                             "docs/options.md", sc.staticTol, &sc.staticTol, nullptr));
  PetscCall(PetscOptionsReal("-gimp_static_min_time",
                             "Earliest time the rest criterion may stop the run [s]",
                             "docs/options.md", sc.staticTime, &sc.staticTime, &o.setStaticTime));
  PetscCall(PetscOptionsReal("-gimp_cfl",
                             "Default time step as a fraction of h / c_p, or of the critical "
                             "step with -gimp_stability_check [-]",
                             "docs/options.md", sc.cfl, &sc.cfl, nullptr));
  PetscBool check = sc.stabilityCheck ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(PetscOptionsBool("-gimp_stability_check",
                             "Critical time step from the largest eigenvalue of M^-1 K (SLEPc)",
                             "docs/options.md", check, &check, nullptr));
  sc.stabilityCheck = check;
  PetscBool multirate = sc.multirate ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(PetscOptionsBool("-gimp_multirate",
                             "A time step per level: level k steps with h_k / h_min times the "
                             "finest step (-ts_dt)",
                             "docs/options.md", multirate, &multirate, nullptr));
  sc.multirate = multirate;
  PetscCall(checkChoice("-gimp_multirate_forces", kRateForces, 2));
  PetscCall(PetscOptionsEList("-gimp_multirate_forces",
                              "How the rate classes' forces reach the nodes with -gimp_multirate: "
                              "impulse (each class's at its own start; for waves) or node (at "
                              "the start of each node's slowest class's step; exact at a static "
                              "state; needs -gimp_update usl)",
                              "docs/options.md", kRateForces, 2, kRateForces[rule], &rule,
                              &setRule));
  sc.multirateNodeRule = rule == 1;
  PetscBool allow = sc.allowUnstableDt ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(PetscOptionsBool("-gimp_allow_unstable_dt",
                             "Accept a -ts_dt above the critical step (for stability studies)",
                             "docs/options.md", allow, &allow, nullptr));
  sc.allowUnstableDt = allow;
  PetscCall(PetscOptionsInt("-gimp_stability_interval",
                            "Steps between re-checks of the critical step (0: at the start only)",
                            "docs/options.md", o.stabilityInterval, &o.stabilityInterval, nullptr));
  PetscCall(PetscOptionsReal("-gimp_memory_limit",
                             "Memory the run may take [bytes] (0: the physical memory of the "
                             "nodes it runs on); larger problems are refused before allocating",
                             "docs/options.md", sc.memoryLimit, &sc.memoryLimit, nullptr));
  PetscOptionsEnd();
  if (setRule && !sc.multirate)
    bad("gimp_multirate_forces", kRateForces[rule], "acts only with -gimp_multirate true");
  return PETSC_SUCCESS;
}

/// The ranges of the options readMethodOptions and readOutputOptions read.
void checkRunOptions(const Scene<2> &sc, const RunOptions &o) {
  if (!o.setH) bad("gimp_h", "(missing)", "the cell size is required, a value > 0 in m");
  if (!(sc.h > 0)) bad("gimp_h", formatNumber(sc.h), "must be > 0 [m]");
  if (sc.damping < 0) bad("gimp_damping", formatNumber(sc.damping), "must be >= 0 [1/s]");
  if (!(sc.flip >= 0 && sc.flip <= 1))
    bad("gimp_flip", formatNumber(sc.flip), "must lie in [0, 1]");
  if (o.setFlip && o.transfer != 0)
    bad("gimp_flip", formatNumber(sc.flip),
        std::string("blends FLIP and PIC only with -gimp_transfer flip, not ") +
            kTransfers[o.transfer]);
  if (o.xpicOrder < 1 || o.xpicOrder > 100)
    bad("gimp_xpic_order", std::to_string(o.xpicOrder), "must be an integer from 1 to 100");
  if (!(sc.massCutoff >= 0 && sc.massCutoff < 1))
    bad("gimp_mass_cutoff", formatNumber(sc.massCutoff), "must lie in [0, 1)");
  if (!(sc.cfl > 0 && sc.cfl <= 1)) bad("gimp_cfl", formatNumber(sc.cfl), "must lie in (0, 1]");
#ifndef GIMP_HAVE_SLEPC
  if (sc.stabilityCheck)
    bad("gimp_stability_check", "true",
        "needs gimp built with SLEPc (install SLEPc and reconfigure); use false");
#endif
  if (o.stabilityInterval < 0 || o.stabilityInterval > INT_MAX)
    bad("gimp_stability_interval", std::to_string(o.stabilityInterval),
        "must be >= 0 steps (0: at the start only)");
  if (o.stabilityInterval > 0 && !sc.stabilityCheck)
    bad("gimp_stability_interval", std::to_string(o.stabilityInterval),
        "needs -gimp_stability_check");
  if (sc.multirate && o.stabilityInterval > 0)
    bad("gimp_stability_interval", std::to_string(o.stabilityInterval),
        "re-checks the single-rate step, not -gimp_multirate's; use 0 with -gimp_multirate");
  if (sc.allowUnstableDt && !sc.stabilityCheck)
    bad("gimp_allow_unstable_dt", "true", "needs -gimp_stability_check");
  if (!(sc.staticTol >= 0 && sc.staticTol < 1))
    bad("gimp_static_tol", formatNumber(sc.staticTol), "must lie in [0, 1) (0: off)");
  if (!(sc.staticTime >= 0))
    bad("gimp_static_min_time", formatNumber(sc.staticTime), "must be >= 0 [s]");

  if (!(sc.cornerSize >= 0.1 && sc.cornerSize <= 0.8))
    bad("gimp_corner_size", formatNumber(sc.cornerSize),
        "must lie in [0.1, 0.8] (fraction of the particle size)");
  if (!(sc.separationThreshold > 0))
    bad("gimp_separation_threshold", formatNumber(sc.separationThreshold), "must be > 0");
  input::checkRunIntervals(sc.outputInterval, sc.historyInterval, sc.monitorInterval,
                           sc.sortInterval);
  if (sc.checkpointInterval < 0)
    bad("gimp_checkpoint_interval", std::to_string(sc.checkpointInterval),
        "must be >= 0 (0: none)");
  if (o.pad < 0) bad("gimp_pad", std::to_string(o.pad), "must be >= 0");
  if (!(sc.memoryLimit >= 0))
    bad("gimp_memory_limit", formatNumber(sc.memoryLimit),
        "must be >= 0 [bytes] (0: the physical memory)");
  if (sc.mms != Mms::None && !(sc.mmsAmplitude > 0))
    bad("gimp_mms_amplitude", formatNumber(sc.mmsAmplitude), "must be > 0 [m]");
}

/// The grid domain: as given, or the bodies' bounding box padded by -gimp_pad cells.
void setDomain(Scene<2> &sc, RunOptions &o) {
  PetscReal *dom = o.dom;
  const PetscInt ndom = o.ndom, pad = o.pad;
  const PetscBool setDom = o.setDom;
  if (setDom) {
    if (ndom != 4) bad("gimp_domain", fmtList(dom, ndom), "needs 4 values x0,y0,x1,y1 [m]");
    if (!(dom[2] > dom[0] && dom[3] > dom[1]))
      bad("gimp_domain", fmtList(dom, 4), "needs x1 > x0 and y1 > y0");
  } else {
    dom[0] = dom[1] = 1e300;
    dom[2] = dom[3] = -1e300;
    for (const Body<2> &b : sc.bodies) {
      dom[0] = std::min(dom[0], b.box[0]);
      dom[1] = std::min(dom[1], b.box[1]);
      dom[2] = std::max(dom[2], b.box[2]);
      dom[3] = std::max(dom[3], b.box[3]);
    }
    dom[0] -= pad * sc.h;
    dom[1] -= pad * sc.h;
    dom[2] += pad * sc.h;
    dom[3] += pad * sc.h;
    // Whole cells from the lower corner.
    dom[2] = dom[0] + std::ceil((dom[2] - dom[0]) / sc.h - 1e-9) * sc.h;
    dom[3] = dom[1] + std::ceil((dom[3] - dom[1]) / sc.h - 1e-9) * sc.h;
  }
  for (int d = 0; d < 2; ++d) {
    const double n = (dom[d + 2] - dom[d]) / sc.h;
    if (std::fabs(n - std::round(n)) > 1e-6 * std::max(1.0, n))
      bad("gimp_domain", fmtList(dom, 4),
          "its extent in " + std::string(d ? "y" : "x") + " (" + formatNumber(dom[d + 2] - dom[d]) +
              " m) is not a whole number of cells of -gimp_h " + formatNumber(sc.h));
    if (std::round(n) < 2)
      bad("gimp_domain", fmtList(dom, 4), "needs at least 2 cells of -gimp_h in each direction");
  }
  std::copy(dom, dom + 4, sc.domain.begin());
  sc.domainGiven = setDom;
  sc.pad = pad;
}

/// The values of the option that gave the body's shape, as the user wrote them.
std::string shapeText(const Body<2> &b) {
  const Shape &s = b.shape;
  if (b.shapeOption == "circle") {
    const double v[3] = {s.cx, s.cy, s.a};
    return fmtList(v, 3);
  }
  if (b.shapeOption == "ellipse") {
    const double v[4] = {s.cx, s.cy, s.a, s.b};
    return fmtList(v, 4);
  }
  if (b.shapeOption == "polygon") return fmtList(s.xy.data(), static_cast<PetscInt>(s.xy.size()));
  if (b.shapeOption == "file") return b.file;
  return fmtList(b.box.data(), 4);
}

/// Bodies do not overlap and lie in the domain; the manufactured solution fits the material.
void checkBodies(const Scene<2> &sc) {
  for (size_t k = 0; k < sc.bodies.size(); ++k)
    for (size_t q = 0; q < k; ++q) {
      const BoxOf<2> &a = sc.bodies[q].box, &b = sc.bodies[k].box;
      if (bodiesOverlap(sc.bodies[q], sc.bodies[k]))
        bad("gimp_body" + std::to_string(k) + "_" + sc.bodies[k].shapeOption,
            shapeText(sc.bodies[k]),
            "overlaps body " + std::to_string(q) + " (bounding box " + fmtList(a.data(), 4) +
                ", body " + std::to_string(k) + "'s " + fmtList(b.data(), 4) +
                "): bodies may touch but not overlap");
    }
  if (sc.mms == Mms::AxialWave &&
      (sc.material.model != MaterialModel::NeoHookean || sc.material.nu != 0 || !sc.oneMaterial))
    bad("gimp_mms", "skb1d",
        "the 1D manufactured solution needs -gimp_material neohookean and -gimp_nu 0 (one "
        "material)");
  // Every particle of a particle file inside the grid domain (seeding places each on the rank
  // that owns its point; none may be lost).
  for (size_t k = 0; k < sc.bodies.size(); ++k) {
    const std::vector<FileParticle> &ps = sc.bodies[k].fromFile.particles;
    for (size_t i = 0; i < ps.size(); ++i)
      if (ps[i].lx > sc.h || ps[i].ly > sc.h) // the stencils reach one level-0 cell
        bad("gimp_body" + std::to_string(k) + "_file", sc.bodies[k].file,
            "particle " + std::to_string(i) + " (data row " + std::to_string(i + 1) +
                ") has half-sizes " + formatNumber(ps[i].lx) + "," + formatNumber(ps[i].ly) +
                " larger than the coarsest cell -gimp_h " + formatNumber(sc.h));
    for (size_t i = 0; i < ps.size(); ++i)
      if (ps[i].x - ps[i].lx < sc.domain[0] || ps[i].x + ps[i].lx > sc.domain[2] ||
          ps[i].y - ps[i].ly < sc.domain[1] || ps[i].y + ps[i].ly > sc.domain[3])
        bad("gimp_body" + std::to_string(k) + "_file", sc.bodies[k].file,
            "particle " + std::to_string(i) + " (data row " + std::to_string(i + 1) + ", at " +
                formatNumber(ps[i].x) + "," + formatNumber(ps[i].y) +
                ") is not inside the grid domain " + fmtList(sc.domain.data(), 4));
  }
  for (size_t k = 0; k < sc.bodies.size(); ++k) {
    const BoxOf<2> &b = sc.bodies[k].box;
    if (b[0] < sc.domain[0] || b[1] < sc.domain[1] || b[2] > sc.domain[2] || b[3] > sc.domain[3])
      bad("gimp_body" + std::to_string(k) + "_" + sc.bodies[k].shapeOption, shapeText(sc.bodies[k]),
          "lies outside the grid domain " + fmtList(sc.domain.data(), 4) + " (bounding box " +
              fmtList(b.data(), 4) + ")");
  }
}

} // namespace

template <> PetscErrorCode readScene<2>(MPI_Comm comm, Scene<2> &sc) {
  PetscBool help = PETSC_FALSE;
  PetscCall(PetscOptionsHasHelp(nullptr, &help));
  sc.help = help;
  RunOptions o;
  PetscCall(readOutputOptions(comm, sc, o));
  PetscCall(readMethodOptions(comm, sc, o));
  PetscCall(readTransferOptions(comm, sc, o));
  sc.name = o.name;
  sc.outputDir = o.outdir[0] ? o.outdir : "output/" + sc.name;
  sc.particleDump = o.pdump;
  sc.gridDump = o.gdump;
  if (!sc.gridDump.empty() && sc.gridDump == sc.particleDump)
    bad("gimp_grid_dump", sc.gridDump, "is the -gimp_particle_dump file too: give two files");
  sc.restart = o.restart;
  sc.holeMeasure = o.setHm;
  std::copy(o.hm, o.hm + 3, sc.hole);
  if (!sc.help && o.setHm && (o.nhm != 3 || !(o.hm[2] > 0)))
    bad("gimp_hole_measure", fmtList(o.hm, o.nhm), "needs cx,cy,r with r > 0 [m]");
  if (!sc.help && o.setHoleLoad && !o.setHm)
    bad("gimp_hole_measure_load", formatNumber(sc.holeLoad),
        "has no effect without -gimp_hole_measure cx,cy,r");
  if (!sc.help && o.setHm && sc.holeLoad == 0)
    bad("gimp_hole_measure_load", "0", "the hole measure needs the remote stress p != 0 [Pa]");
  sc.update = static_cast<Update>(o.update);
  sc.transfer = static_cast<Transfer>(o.transfer);
  if (!o.setCutoff) sc.massCutoff = MethodOptions::defaultMassCutoff(sc.transfer);
  sc.xpicOrder = static_cast<int>(o.xpicOrder);
  sc.tracking = static_cast<Tracking>(o.tracking);
  sc.mms = static_cast<Mms>(o.mms);
  sc.stabilityInterval = static_cast<int>(std::min<PetscInt>(o.stabilityInterval, INT_MAX));
  PetscCall(readMaterial(comm, sc));
  PetscCall(readBodies(comm, sc));
  PetscCall(readLoads(comm, sc));
  if (sc.help) {
    PetscCall(readLevels(comm, sc));
    return readCracks(comm, sc);
  }
  checkRunOptions(sc, o);
  // (A warning, not an error: a file that includes another may turn its rest criterion off.)
  if (o.setStaticTime && sc.staticTol == 0)
    PetscCall(PetscPrintf(comm,
                          "gimp: warning: -gimp_static_min_time %s has no effect: the rest "
                          "criterion is off (-gimp_static_tol 0)\n",
                          formatNumber(sc.staticTime).c_str()));
  setDomain(sc, o);
  PetscCall(readLevels(comm, sc));
  checkBodies(sc);
  return readCracks(comm, sc);
}

} // namespace gimp
