#include "gimp/input/validate.hpp"

#include "gimp/input/options.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <new>
#include <sstream>
#include <vector>

namespace gimp {

namespace {

/// The first PETSc error of a call: its code and message.
struct PetscFirstError {
  PetscErrorCode code = PETSC_SUCCESS;
  std::string message;
};

/// While options are read, PETSc's own parsing errors are kept as one message.
PetscErrorCode keepInputError(MPI_Comm, int, const char *, const char *, PetscErrorCode n,
                              PetscErrorType p, const char *mess, void *ctx) {
  auto *first = static_cast<PetscFirstError *>(ctx);
  if (p == PETSC_ERROR_INITIAL) {
    first->code = n;
    if (mess) first->message = mess;
  }
  return n;
}

/// The option whose value appears in PETSc's message ("Input string abc has ...",
/// "Unknown logical value: maybe"), to name it in the one-line error.
std::string optionWithValueIn(const std::string &message) {
  char *all = nullptr;
  if (PetscOptionsGetAll(nullptr, &all) || !all) return "";
  std::istringstream in(all);
  std::string tok, name, found;
  while (in >> tok) {
    if (tok.size() > 1 && tok[0] == '-' && !std::isdigit(static_cast<unsigned char>(tok[1])) &&
        tok[1] != '.') {
      name = tok;
      continue;
    }
    // The value, or a part of a viewer's TYPE:FILE:FORMAT (PETSc names the part it refused).
    bool named = false;
    for (size_t at = 0; at <= tok.size() && !named;) {
      const size_t colon = std::min(tok.find(':', at), tok.size());
      const std::string part = at == 0 && colon == tok.size() ? tok : tok.substr(at, colon - at);
      named = !part.empty() &&
              (message.find(" " + part + " ") != std::string::npos ||
               (message.size() >= part.size() &&
                message.compare(message.size() - part.size(), part.size(), part) == 0));
      at = colon + 1;
    }
    if (!name.empty() && named) found = name + " " + tok;
  }
  (void)PetscFree(all);
  return found;
}

/// The options set whose names start with -prefix, as "-name value" joined by spaces.
std::string optionsWithPrefix(const std::string &prefix) {
  char *all = nullptr;
  if (prefix.empty() || PetscOptionsGetAll(nullptr, &all) || !all) return "";
  std::istringstream in(all);
  std::string tok, found;
  bool inside = false;
  while (in >> tok) {
    const bool name = tok.size() > 1 && tok[0] == '-' &&
                      !std::isdigit(static_cast<unsigned char>(tok[1])) && tok[1] != '.';
    if (name) inside = tok.compare(1, prefix.size(), prefix) == 0;
    if (inside) found += (found.empty() || name ? (found.empty() ? "" : ", ") : " ") + tok;
  }
  (void)PetscFree(all);
  return found;
}

/// Run `read` with PETSc's error handler replaced; a PETSc error becomes one InputError line,
/// naming the option whose value PETSc's message holds, else those set under `prefix`.
template <class Read>
PetscErrorCode readOneLine(Read read, const std::string &prefix = "",
                           const std::string &hint = "") {
  PetscFirstError first;
  PetscCall(PetscPushErrorHandler(keepInputError, &first));
  PetscErrorCode ierr = PETSC_SUCCESS;
  try {
    ierr = read();
  } catch (...) {
    PetscCall(PetscPopErrorHandler());
    throw;
  }
  PetscCall(PetscPopErrorHandler());
  // Out of memory (main: one line, every rank ends): PETSc's code, or the swarm's resize, whose
  // failed realloc comes with its function's name and a code of its own.
  if (ierr == PETSC_ERR_MEM || first.code == PETSC_ERR_MEM ||
      first.message.find("DMSwarmDataFieldSetSize") != std::string::npos)
    throw std::bad_alloc();
  if (ierr) {
    const std::string &petscMessage = first.message;
    std::string opt = optionWithValueIn(petscMessage);
    if (const std::string set = optionsWithPrefix(prefix);
        !set.empty() && opt.compare(0, prefix.size() + 1, "-" + prefix) != 0)
      opt = set;
    throw InputError((opt.empty() ? std::string("options: ") : "option " + opt + ": ") +
                     petscMessage + hint);
  }
  return PETSC_SUCCESS;
}

/// The declared kind of a gimp option, or of the time stepper's step, end time and step count.
const input::OptionSpec *declared(const std::string &name) {
  return name.rfind("gimp_", 0) == 0 ? input::findOption(name) : nullptr;
}

bool isLogical(const std::string &name) {
  const input::OptionSpec *s = declared(name);
  return s && s->kind == input::Kind::Bool;
}

/// Options whose value is a word (a name, a path or a choice), not numbers.
bool isWord(const std::string &name) {
  const input::OptionSpec *s = declared(name);
  return s && (s->kind == input::Kind::Word || s->kind == input::Kind::Choice);
}

/// Options PETSc reads as one PetscInt: it keeps a value too large for one wrapped around.
bool isInteger(const std::string &name) {
  if (name == "ts_max_steps") return true;
  const input::OptionSpec *s = declared(name);
  return s && s->kind == input::Kind::Int;
}

/// An integer literal outside PetscInt's range.
bool overflowsPetscInt(const std::string &value) {
  char *end = nullptr;
  errno = 0;
  const long long v = std::strtoll(value.c_str(), &end, 10);
  return end != value.c_str() && *end == '\0' &&
         (errno == ERANGE || v > PETSC_MAX_INT || v < PETSC_MIN_INT);
}

/// Every number in a comma-separated value is finite ("nan", "inf", 1e999 are not).
bool allFinite(const std::string &value) {
  size_t at = 0;
  while (at <= value.size()) {
    const size_t comma = std::min(value.find(',', at), value.size());
    const std::string token = value.substr(at, comma - at);
    char *end = nullptr;
    const double v = std::strtod(token.c_str(), &end);
    if (end != token.c_str() && *end == '\0' && !std::isfinite(v)) return false;
    at = comma + 1;
  }
  return true;
}

/// In a comma-separated list of numbers, the first element that is empty or not a number (PETSc
/// drops empty elements and names no option for a bad one): "" when every element is a number,
/// or when none is (a list of words, which may not have an empty element either).
std::string badListElement(const std::string &value) {
  if (value.find(',') == std::string::npos) return "";
  std::vector<std::string> tokens;
  size_t at = 0;
  while (at <= value.size()) {
    const size_t comma = std::min(value.find(',', at), value.size());
    tokens.push_back(value.substr(at, comma - at));
    at = comma + 1;
  }
  const auto isNumber = [](const std::string &t) {
    char *end = nullptr;
    (void)std::strtod(t.c_str(), &end);
    return !t.empty() && end != t.c_str() && *end == '\0';
  };
  for (size_t i = 0; i < tokens.size(); ++i)
    if (tokens[i].empty()) return "element " + std::to_string(i + 1) + " is empty";
  if (std::none_of(tokens.begin(), tokens.end(), isNumber)) return "";
  for (size_t i = 0; i < tokens.size(); ++i)
    if (!isNumber(tokens[i]))
      return "element " + std::to_string(i + 1) + " (" + tokens[i] + ") is not a number";
  return "";
}

/// Before anything is read: every gimp option and the time stepper's step, end time and step
/// count have a value (PETSc would silently keep the default of an option given alone), and
/// every number in them is finite (a NaN passes checks written as x < 0).
PetscErrorCode checkOptionValues() {
  PetscInt n = 0;
  char **names = nullptr, **values = nullptr;
  PetscCall(PetscOptionsLeftGet(nullptr, &n, &names, &values));
  std::string error;
  for (PetscInt i = 0; i < n && error.empty(); ++i) {
    const std::string name = names[i], value = values[i] ? values[i] : "";
    const bool ts = name == "ts_dt" || name == "ts_max_time" || name == "ts_max_steps";
    if ((name.rfind("gimp_", 0) != 0 && !ts) || isLogical(name)) continue;
    if (value.empty())
      error = "option -" + name + ": needs a value after it (see -help and docs/options.md)";
    else if (!isWord(name) && !allFinite(value))
      error = "option -" + name + " " + value + ": the values must be finite numbers";
    else if (const std::string bad = isWord(name) ? "" : badListElement(value); !bad.empty())
      error = "option -" + name + " " + value + ": " + bad +
              " (a list of numbers separated by commas; see docs/options.md)";
    else if (isInteger(name) && overflowsPetscInt(value))
      error = "option -" + name + " " + value + ": must be an integer from " +
              std::to_string(PETSC_MIN_INT) + " to " + std::to_string(PETSC_MAX_INT);
  }
  PetscCall(PetscOptionsLeftRestore(nullptr, &n, &names, &values));
  if (!error.empty()) throw InputError(error);
  return PETSC_SUCCESS;
}

} // namespace

template <int D> PetscErrorCode readSceneOneLine(MPI_Comm comm, Scene<D> &sc) {
  return readOptionsOneLine([&] { return readScene<D>(comm, sc); });
}

PetscErrorCode petscOneLine(const std::function<PetscErrorCode()> &call, const std::string &prefix,
                            const std::string &hint) {
  return readOneLine(call, prefix, hint);
}

PetscErrorCode checkViewerOptions(MPI_Comm comm) {
  // Opened and closed once here: a viewer PETSc would open at the end (-ts_view after the last
  // step, -log_view at exit) fails now, in one line, rather than after the run.
  for (const char *name : {"-ts_view", "-log_view"}) {
    PetscViewer viewer = nullptr;
    PetscViewerFormat format;
    PetscBool set = PETSC_FALSE;
    try {
      PetscCall(readOneLine(
          [&] {
            return PetscOptionsGetViewer(comm, nullptr, nullptr, name, &viewer, &format, &set);
          },
          name + 1));
    } catch (const InputError &) { // PETSc would meet it again at exit (-log_view)
      PetscCall(PetscOptionsClearValue(nullptr, name));
      throw;
    }
    if (viewer) PetscCall(PetscViewerDestroy(&viewer));
  }
  return PETSC_SUCCESS;
}

PetscErrorCode readOptionsOneLine(const std::function<PetscErrorCode()> &read) {
  PetscBool help = PETSC_FALSE;
  PetscCall(PetscOptionsHasHelp(nullptr, &help));
  if (!help) PetscCall(checkOptionValues());
  return readOneLine(read);
}

/// -gimp_levelK_follow against the scene: the crack tip or probe exists, finer levels follow the
/// same point (a fixed box inside a moving one would leave it), no rate classes.
template <int D> void checkFollow(const Scene<D> &sc) {
  for (size_t k = 1; k < sc.follow.size(); ++k) {
    const LevelFollow &f = sc.follow[k];
    if (f.kind == LevelFollow::Kind::None) continue;
    const std::string name = "option -gimp_level" + std::to_string(k) + "_follow ";
    const std::string what =
        f.kind == LevelFollow::Kind::Probe ? "probe" + std::to_string(f.index)
        : f.kind == LevelFollow::Kind::CrackFront
            ? "crack" + std::to_string(f.index) + "_front"
            : "crack" + std::to_string(f.index) + "_tip" + std::to_string(f.end);
    if (sc.multirate)
      throw InputError(name + what +
                       ": not built with -gimp_multirate true (its rate classes are built once "
                       "for the levels as they are); use -gimp_multirate false");
    if (f.kind == LevelFollow::Kind::Probe && static_cast<size_t>(f.index) >= sc.probes.size())
      throw InputError(name + what + ": the scene has " + std::to_string(sc.probes.size()) +
                       " probes (-gimp_probes); give probeN with N below that");
    if (f.kind == LevelFollow::Kind::CrackFront) {
      if constexpr (D == 2)
        throw InputError(name + what +
                         ": crack fronts are the edges of 3D crack polygons; a 2D crack has tips "
                         "(crackC_tipT)");
      if (static_cast<size_t>(f.index) >= sc.cracks.size())
        throw InputError(name + what + ": the scene has " + std::to_string(sc.cracks.size()) +
                         " cracks (-gimp_cracks)");
    }
    if (f.kind == LevelFollow::Kind::CrackTip) {
      if constexpr (D == 3) {
        throw InputError(name + what +
                         ": crack tips are points of 2D cracks; a 3D crack has a front (follow "
                         "crack" +
                         std::to_string(f.index) + "_front)");
      } else {
        if (static_cast<size_t>(f.index) >= sc.cracks.size())
          throw InputError(name + what + ": the scene has " + std::to_string(sc.cracks.size()) +
                           " cracks (-gimp_cracks)");
        if (!sc.cracks[f.index].tip[f.end])
          throw InputError(name + what + ": that end of the crack is a mouth (on or outside a " +
                           "body's edge), not a tip");
      }
    }
    for (size_t q = k + 1; q < sc.follow.size(); ++q)
      if (!(sc.follow[q] == f))
        throw InputError("option -gimp_level" + std::to_string(q) + "_follow: level " +
                         std::to_string(q) + " lies in level " + std::to_string(k) +
                         ", which follows " + what + "; it must follow the same point (give -" +
                         "gimp_level" + std::to_string(q) + "_follow " + what + ")");
  }
}

template <int D> void checkSceneCombinations(const Scene<D> &sc) {
  checkFollow(sc);
  // Crack growth changes the cracks between steps; a coarse step's rate classes keep their
  // stencils across it (docs/method.md, *Crack growth*).
  if (sc.multirate && sc.growth != Growth::None)
    throw InputError("option -gimp_crack_growth mts: not built with -gimp_multirate true (its rate "
                     "classes keep their crack fields over a coarse step); use -gimp_multirate "
                     "false");
  // A rate class's crack fields and faces are built in 2D only (MultiRate::startClass).
  if (D == 3 && sc.multirate && !sc.cracks.empty())
    throw InputError("option -gimp_multirate true: not built with 3D cracks (a rate class's crack "
                     "fields and faces exist in 2D only); use -gimp_multirate false");
  // -gimp_multirate is built for tensor-product GIMP weights with the FLIP/PIC blend or APIC, and
  // with cracks for PIC or APIC (docs/method.md, "Multi-rate time steps per level").
  if (sc.multirate && !sc.cracks.empty() && sc.transfer == Transfer::Flip && sc.flip > 0)
    throw InputError("option -gimp_flip " + formatNumber(sc.flip) +
                     ": with cracks and -gimp_multirate true the velocities must be PIC or APIC "
                     "(-gimp_flip 0 or -gimp_transfer apic): crack contact changes the nodal "
                     "velocities, which the FLIP shares of the rate classes do not follow");
  if (sc.multirate && (tracksCorners(sc.tracking) || usesCpdi(sc.tracking)))
    throw InputError("option -gimp_multirate true: not built with corner or CPDI tracking "
                     "(-gimp_tracking corners, cpdi, cpdi2); use none, strain or stretch, or "
                     "-gimp_multirate false");
  if (sc.multirate && !sc.multirateNodeRule && sc.staticTol > 0)
    throw InputError("option -gimp_static_tol " + formatNumber(sc.staticTol) +
                     ": a run to rest with -gimp_multirate true needs -gimp_multirate_forces "
                     "node and -gimp_update usl; with the impulse rule (the default) the nodes "
                     "that slower and faster classes share keep oscillating at a static state "
                     "(docs/method.md)");
  if (sc.multirate && sc.multirateNodeRule && sc.update != Update::USL)
    throw InputError("option -gimp_multirate_forces node: needs -gimp_update usl (with musl each "
                     "rate class updates its stress with its own share of the re-projection, "
                     "which locks a stress into the class borders at rest: 0.2 % of the load "
                     "with FLIP, 53 % with PIC; docs/method.md)");
  if (sc.multirate && sc.update == Update::USF)
    throw InputError("option -gimp_multirate true: not built with -gimp_update usf (its stress "
                     "update before the impulses grows at level interfaces); use musl or usl, or "
                     "-gimp_multirate false");
  if (sc.multirate && sc.transfer == Transfer::Xpic)
    throw InputError("option -gimp_multirate true: not built with -gimp_transfer xpic; use flip "
                     "or apic, or -gimp_multirate false");
  if (sc.material.model == MaterialModel::NeoHookean && !sc.material.planeStrain)
    throw InputError("option -gimp_material neohookean: needs -gimp_plane strain (the plane-stress "
                     "neo-Hookean model is not implemented)");
  for (size_t b = 0; b < sc.bodies.size(); ++b)
    if (sc.bodies[b].material.model == MaterialModel::NeoHookean && !sc.material.planeStrain)
      throw InputError("option -gimp_body" + std::to_string(b) +
                       "_material neohookean: needs -gimp_plane strain (the plane-stress "
                       "neo-Hookean model is not implemented)");
  if constexpr (D == 2) // (the ids of 2D particles hold 64 x 64 sub-cells)
    for (size_t b = 0; b < sc.bodies.size(); ++b)
      if (std::max(sc.bodies[b].ppc, sc.bodies[b].holePpc) > 64 * 64)
        throw InputError("option -gimp_body" + std::to_string(b) +
                         "_ppc: at most 4096 particles per cell (64 x 64)");
}

template <int D>
PetscErrorCode timeStepFromOptions(TS ts, const Scene<D> &sc, const Lattice<D> &grid) {
  return timeStepFromOptions(ts, sc.maxWaveSpeed(), grid.hMin(), sc.stabilityCheck, sc.damping);
}

PetscErrorCode timeStepFromOptions(TS ts, double cp, double hMin, bool unstableAllowed,
                                   double damping) {
  PetscCall(readOneLine([&] { return TSSetFromOptions(ts); }));
  TSType type;
  TSAdapt adapt;
  TSAdaptType atype;
  PetscCall(TSGetType(ts, &type));
  PetscCall(TSGetAdapt(ts, &adapt));
  PetscCall(TSAdaptGetType(adapt, &atype));
  TSExactFinalTimeOption exact;
  PetscCall(TSGetExactFinalTime(ts, &exact));
  if (exact == TS_EXACTFINALTIME_INTERPOLATE)
    throw InputError("option -ts_exact_final_time interpolate: not available (the particles "
                     "cannot be interpolated back to -ts_max_time); use matchstep (the last step "
                     "shortened to end on -ts_max_time) or stepover (the default)");
  if (std::string(type) != TSEULER)
    throw InputError("option -ts_type " + std::string(type) +
                     ": gimp advances the nodal momentum with euler (Eq. 16); use -ts_type euler");
  if (std::string(atype) != TSADAPTNONE)
    throw InputError("option -ts_adapt_type " + std::string(atype) +
                     ": the time step is fixed (-ts_dt); use -ts_adapt_type none");
  PetscInt maxSteps = 0;
  PetscReal dt = 0, maxTime = 0;
  PetscCall(TSGetMaxSteps(ts, &maxSteps));
  PetscCall(TSGetMaxTime(ts, &maxTime));
  if (maxSteps < 0)
    throw InputError("option -ts_max_steps " + std::to_string(maxSteps) + ": must be >= 0");
  if (!(maxTime > 0))
    throw InputError("option -ts_max_time " + formatNumber(maxTime) + ": must be > 0 [s]");
  PetscCall(TSGetTimeStep(ts, &dt));
  const double dtStable = hMin / cp;
  if (!(dt > 0)) throw InputError("option -ts_dt " + formatNumber(dt) + ": must be > 0 [s]");
  if (dt > dtStable && !unstableAllowed)
    throw InputError("option -ts_dt " + formatNumber(dt) +
                     ": exceeds the stable limit h / c_p = " + formatNumber(dtStable) +
                     " s (finest h = " + formatNumber(hMin) + " m, c_p = " + formatNumber(cp) +
                     " m/s); choose -ts_dt <= " + formatNumber(dtStable));
  // Damping lowers the limit: the leapfrog step with the force -d p on the momentum keeps a mode
  // of frequency w = 2 c_p / h stable for dt < (2 / w)(sqrt(1 + xi^2) - xi), xi = d / (2 w)
  // (docs/validation.md, *Unstable runs*). A warning, as this bound is only as sharp as w (GIMP's
  // highest frequency can lie below 2 c_p / h); -gimp_stability_check gives the step's own.
  const double xi = damping * hMin / (4.0 * cp);
  const double dtDamped = dtStable * (std::sqrt(1.0 + xi * xi) - xi);
  if (damping > 0 && dt > dtDamped && !unstableAllowed)
    PetscCall(PetscPrintf(PetscObjectComm(reinterpret_cast<PetscObject>(ts)),
                          "gimp: warning: -ts_dt %s s exceeds the stable limit of the damped "
                          "step, (h / c_p)(sqrt(1 + xi^2) - xi) = %s s with xi = d h / (4 c_p) = "
                          "%s (-gimp_damping %s): the run will likely go unstable; choose -ts_dt "
                          "<= %s\n",
                          formatNumber(dt).c_str(), formatNumber(dtDamped).c_str(),
                          formatNumber(xi).c_str(), formatNumber(damping).c_str(),
                          formatNumber(dtDamped).c_str()));
  return PETSC_SUCCESS;
}

PetscErrorCode rejectUnusedOptions() {
  PetscInt nleft = 0;
  char **names = nullptr, **values = nullptr;
  PetscCall(PetscOptionsLeftGet(nullptr, &nleft, &names, &values));
  std::string unknown;
  const char *lateOptions[] = {
      "log_view",        "log_all",     "log_trace",   "options_left", "options_view",
      "malloc_dump",     "malloc_view", "memory_view", "objects_dump", "check_pointer_intensity",
      "log_view_memory", "info",        "ts_view"};
  for (PetscInt i = 0; i < nleft && unknown.empty(); ++i) {
    bool late = false;
    for (const char *o : lateOptions)
      if (std::string(names[i]).rfind(o, 0) == 0) late = true;
    if (!late) unknown = std::string(names[i]) + (values[i] ? std::string(" ") + values[i] : "");
  }
  PetscCall(PetscOptionsLeftRestore(nullptr, &nleft, &names, &values));
  if (unknown.empty()) return PETSC_SUCCESS;
  throw InputError("option -" + unknown +
                   ": unknown option (misspelled, or not used by this scene); see -help and "
                   "docs/options.md");
  return PETSC_SUCCESS;
}

#define GIMP_INSTANTIATE(D)                                                                        \
  template PetscErrorCode readSceneOneLine<D>(MPI_Comm, Scene<D> &);                               \
  template void checkSceneCombinations<D>(const Scene<D> &);                                       \
  template PetscErrorCode timeStepFromOptions<D>(TS, const Scene<D> &, const Lattice<D> &);
GIMP_INSTANTIATE(2)
GIMP_INSTANTIATE(3)
#undef GIMP_INSTANTIATE

} // namespace gimp
