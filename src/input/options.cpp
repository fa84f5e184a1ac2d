// Reading an option by its declaration (input/options.hpp): the PETSc call that lists it in
// -help, the value count of its dimension, its check, and the refusal of an option (or a choice)
// of the other dimension with the feature table's reason.
#include "gimp/input/options.hpp"

#include <petscsys.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>

namespace gimp::input {

namespace {

/// "gimp_body3_add_polygon12" -> "gimp_bodyK_add_polygonJ": the first index K, the second J.
std::string familyName(const std::string &name) {
  std::string r;
  int runs = 0;
  for (size_t i = 0; i < name.size(); ++i) {
    if (!std::isdigit(static_cast<unsigned char>(name[i]))) {
      r += name[i];
      continue;
    }
    while (i + 1 < name.size() && std::isdigit(static_cast<unsigned char>(name[i + 1])))
      ++i;
    r += runs++ == 0 ? 'K' : 'J';
  }
  return r;
}

std::string strip(const std::string &name) {
  return !name.empty() && name[0] == '-' ? name.substr(1) : name;
}

/// The choices of a Choice option ("a|b|c").
std::vector<std::string> split(const std::string &s, char sep) {
  std::vector<std::string> out;
  size_t at = 0;
  while (at <= s.size()) {
    const size_t next = std::min(s.find(sep, at), s.size());
    out.push_back(s.substr(at, next - at));
    at = next + 1;
  }
  return out;
}

/// How many values a Reals option takes and whether they are groups (",..." at the end).
struct Count {
  size_t n = 0;
  bool groups = false;
  std::string what; // the values without ",..."
};
Count countOf(const char *values) {
  Count c;
  std::string v = values ? values : "";
  if (v.size() > 4 && v.compare(v.size() - 4, 4, ",...") == 0) {
    c.groups = true;
    v.resize(v.size() - 4);
  }
  c.what = v;
  c.n = v.empty() ? 0 : static_cast<size_t>(std::count(v.begin(), v.end(), ',')) + 1;
  // A polygon's vertices, a crack's points: pairs.
  if (c.groups && c.what == "x0,y0,x1,y1") c.n = 2;
  return c;
}

std::string unitText(const OptionSpec &s) {
  return *s.unit ? std::string(" [") + s.unit + "]" : "";
}

/// The help text PETSc lists for option s in dimension dim.
std::string helpText(const OptionSpec &s, int dim) {
  std::string h = s.help;
  if (s.kind == Kind::Reals || s.kind == Kind::Ramp) h += ": " + std::string(s.values(dim));
  return h + unitText(s);
}

/// The -help section of option `name`: one per declared option (PETSc prints a section title
/// once, and the options of a later section of the same title not at all).
std::string titleOf(const std::string &name) {
  return "gimp option -" + familyName(name);
}

/// PETSc's option calls inside PetscOptionsBegin/End (so that -help lists them), with a PETSc
/// error (a value that is not a number, ...) returned as its code for readOptionsOneLine.
template <class Fn> void petscOptions(MPI_Comm comm, const std::string &name, Fn &&fn) {
  const std::string title = titleOf(name);
  auto inner = [&]() -> PetscErrorCode {
    PetscOptionsBegin(comm, nullptr, title.c_str(), "gimp");
    PetscCall(fn(PetscOptionsObject));
    PetscOptionsEnd();
    return PETSC_SUCCESS;
  };
  if (const PetscErrorCode ierr = inner()) throw OptionsReadError{ierr};
}

/// The value given for `name` as text ("" when not given).
std::string givenText(const std::string &name) {
  char buf[4096];
  PetscBool set = PETSC_FALSE;
  if (PetscOptionsGetString(nullptr, nullptr, ("-" + name).c_str(), buf, sizeof(buf), &set) || !set)
    return "";
  return buf;
}

} // namespace

std::string fmtList(const double *v, size_t n) {
  std::string r;
  for (size_t i = 0; i < n; ++i)
    r += (i ? "," : "") + formatNumber(v[i]);
  return r;
}

std::string Check::rule() const {
  const auto f = [](double v) { return formatNumber(v); };
  switch (op) {
  case None:
    return "";
  case Above:
    return "must be > " + f(lo);
  case AtLeast:
    return "must be >= " + f(lo);
  case Within:
    if (integer) return "must be an integer from " + f(lo) + " to " + f(hi);
    return "must lie in " + std::string(openLo ? "(" : "[") + f(lo) + ", " + f(hi) +
           (openHi ? ")" : "]");
  }
  return "";
}

bool Check::holds(double v) const {
  switch (op) {
  case None:
    return true;
  case Above:
    return v > lo;
  case AtLeast:
    return v >= lo;
  case Within:
    return (openLo ? v > lo : v >= lo) && (openHi ? v < hi : v <= hi) &&
           (!integer || v == std::round(v));
  }
  return true;
}

const OptionSpec *findOption(const std::string &name) {
  static const std::map<std::string, const OptionSpec *> byName = [] {
    std::map<std::string, const OptionSpec *> m;
    for (const OptionSpec &s : optionTable())
      m[s.name] = &s;
    return m;
  }();
  const auto it = byName.find(familyName(strip(name)));
  return it == byName.end() ? nullptr : it->second;
}

const Feature *featureOf(const std::string &name, const std::string &value) {
  const std::string f = familyName(strip(name)), withValue = f + "=" + value;
  for (const Feature &feature : featureTable())
    for (const char *o : feature.options)
      if (f == o || (!value.empty() && withValue == o)) return &feature;
  return nullptr;
}

Dims dimsOf(const std::string &name, const std::string &value) {
  const Feature *f = featureOf(name, value);
  return f ? f->dims : InBoth;
}

void Options::bad(const std::string &name, const std::string &value, const std::string &valid) {
  throw InputError("option -" + strip(name) + " " + value + ": " + valid);
}

bool Options::given(const std::string &name) const {
  PetscBool set = PETSC_FALSE;
  (void)PetscOptionsHasName(nullptr, nullptr, ("-" + strip(name)).c_str(), &set);
  return set;
}

std::string Options::givenValue(const std::string &name) const {
  const std::string v = givenText(strip(name));
  return v.empty() ? "(given)" : v;
}

void Options::needs(bool has, const std::string &name, const std::string &what) const {
  if (!help_ && !has && given(name)) bad(name, givenText(strip(name)), "acts only with " + what);
}

const OptionSpec &Options::spec(const std::string &name) const {
  const OptionSpec *s = findOption(name);
  if (!s) throw InputError("option -" + name + ": not declared in the option table");
  if (!help_ && given(name))
    if (const Feature *f = featureOf(name); f && !(f->dims & (dim_ == 2 ? In2D : In3D)))
      bad(name, givenText(name),
          std::string("not available with -gimp_dim ") + std::to_string(dim_) + " (" + f->what +
              "): " + f->why);
  return *s;
}

void Options::check(const std::string &name, const OptionSpec &s, double v) const {
  if (!help_ && !s.check.holds(v)) bad(name, formatNumber(v), s.check.rule() + unitText(s));
}

double Options::real(const std::string &name, double def, bool *given) const {
  const OptionSpec &s = spec(name);
  PetscReal v = def;
  PetscBool set = PETSC_FALSE;
  const std::string help = helpText(s, dim_), opt = "-" + name;
  petscOptions(comm_, name, [&](PetscOptionItems *PetscOptionsObject) {
    return PetscOptionsReal(opt.c_str(), help.c_str(), "docs/options.md", v, &v, &set);
  });
  if (set) check(name, s, v);
  if (given) *given = set;
  return v;
}

PetscInt Options::integer(const std::string &name, PetscInt def, bool *given) const {
  const OptionSpec &s = spec(name);
  PetscInt v = def;
  PetscBool set = PETSC_FALSE;
  const std::string help = helpText(s, dim_), opt = "-" + name;
  petscOptions(comm_, name, [&](PetscOptionItems *PetscOptionsObject) {
    return PetscOptionsInt(opt.c_str(), help.c_str(), "docs/options.md", v, &v, &set);
  });
  if (set) check(name, s, static_cast<double>(v));
  if (given) *given = set;
  return v;
}

bool Options::flag(const std::string &name, bool def, bool *given) const {
  const OptionSpec &s = spec(name);
  PetscBool v = def ? PETSC_TRUE : PETSC_FALSE, set = PETSC_FALSE;
  const std::string help = helpText(s, dim_), opt = "-" + name;
  petscOptions(comm_, name, [&](PetscOptionItems *PetscOptionsObject) {
    return PetscOptionsBool(opt.c_str(), help.c_str(), "docs/options.md", v, &v, &set);
  });
  if (given) *given = set;
  return v;
}

std::string Options::word(const std::string &name, const std::string &def, bool *given) const {
  const OptionSpec &s = spec(name);
  char buf[PETSC_MAX_PATH_LEN];
  std::snprintf(buf, sizeof(buf), "%s", def.c_str());
  PetscBool set = PETSC_FALSE;
  const std::string help = helpText(s, dim_), opt = "-" + name;
  petscOptions(comm_, name, [&](PetscOptionItems *PetscOptionsObject) {
    return PetscOptionsString(opt.c_str(), help.c_str(), "docs/options.md", buf, buf, sizeof(buf),
                              &set);
  });
  if (given) *given = set;
  return buf;
}

std::string Options::choice(const std::string &name, const std::string &def, bool *given) const {
  const OptionSpec &s = spec(name);
  const Dims mine = dim_ == 2 ? In2D : In3D;
  std::vector<std::string> all = split(s.values(dim_), '|'), here;
  for (const std::string &c : all)
    if (dimsOf(name, c) & mine) here.push_back(c);
  const std::string value = givenText(name);
  if (!help_ && this->given(name)) {
    const bool known = std::find(all.begin(), all.end(), value) != all.end();
    if (const Feature *f = featureOf(name, value); known && f && !(f->dims & mine))
      bad(name, value,
          std::string("not available with -gimp_dim ") + std::to_string(dim_) + " (" + f->what +
              "): " + f->why);
    if (std::find(here.begin(), here.end(), value) == here.end()) {
      std::string valid;
      for (const std::string &c : here)
        valid += (valid.empty() ? "" : ", ") + c;
      bad(name, value, "must be one of " + valid);
    }
  }
  std::vector<const char *> list;
  for (const std::string &c : here)
    list.push_back(c.c_str());
  const auto d = std::find(here.begin(), here.end(), def);
  PetscInt v = d == here.end() ? 0 : static_cast<PetscInt>(d - here.begin());
  PetscBool set = PETSC_FALSE;
  const std::string help = helpText(s, dim_), opt = "-" + name;
  petscOptions(comm_, name, [&](PetscOptionItems *PetscOptionsObject) {
    return PetscOptionsEList(opt.c_str(), help.c_str(), "docs/options.md", list.data(),
                             static_cast<PetscInt>(list.size()), list[v], &v, &set);
  });
  if (given) *given = set;
  return set ? here[static_cast<size_t>(v)] : def;
}

std::vector<double> Options::reals(const std::string &name, bool required) const {
  const OptionSpec &s = spec(name);
  const Count c = countOf(s.values(dim_));
  std::vector<PetscReal> buf(c.groups ? 1201 : c.n + 1);
  PetscInt got = static_cast<PetscInt>(buf.size());
  PetscBool set = PETSC_FALSE;
  const std::string help = helpText(s, dim_), opt = "-" + name;
  petscOptions(comm_, name, [&](PetscOptionItems *PetscOptionsObject) {
    return PetscOptionsRealArray(opt.c_str(), help.c_str(), "docs/options.md", buf.data(), &got,
                                 &set);
  });
  if (help_) return {};
  const std::string needs =
      "needs " +
      (!c.groups  ? std::to_string(c.n) + (c.n == 1 ? " value " : " values ") + c.what
       : c.n == 2 ? "pairs x,y (" + c.what + ",...)"
                  : "groups of " + std::to_string(c.n) + " values " + c.what) +
      unitText(s);
  if (!set) {
    if (required) bad(name, "(missing)", needs);
    return {};
  }
  const size_t n = static_cast<size_t>(got);
  if (c.groups && n >= buf.size()) bad(name, "(more than 1200 values)", "at most 1200 values");
  if (c.groups ? n == 0 || n % c.n != 0 : n != c.n) bad(name, fmtList(buf.data(), n), needs);
  for (size_t i = 0; i < n; ++i)
    if (!std::isfinite(buf[i])) bad(name, fmtList(buf.data(), n), "the values must be finite");
  return {buf.begin(), buf.begin() + static_cast<long>(n)};
}

Ramp Options::ramp(const std::string &name) const {
  const OptionSpec &s = spec(name);
  std::vector<PetscReal> v(201);
  PetscInt n = 201;
  PetscBool set = PETSC_FALSE;
  const std::string help = helpText(s, dim_), opt = "-" + name;
  petscOptions(comm_, name, [&](PetscOptionItems *PetscOptionsObject) {
    return PetscOptionsRealArray(opt.c_str(), help.c_str(), "docs/options.md", v.data(), &n, &set);
  });
  Ramp r;
  if (!set || help_) return r;
  const std::string all = fmtList(v.data(), static_cast<size_t>(n));
  if (n > 200) bad(name, "(more than 100 pairs)", "at most 100 pairs t,f");
  if (n < 2 || n % 2) bad(name, all, "needs pairs t,f (at least one)");
  for (PetscInt i = 0; i < n; i += 2) {
    if (i > 0 && !(v[i] > v[i - 2])) bad(name, all, "times must increase strictly");
    r.t.push_back(v[i]);
    r.f.push_back(v[i + 1]);
  }
  return r;
}

} // namespace gimp::input

namespace gimp::input {

bool isPerfectSquare(int n) {
  const int r = static_cast<int>(std::lround(std::sqrt(static_cast<double>(n))));
  return n > 0 && r * r == n;
}

void refuseOtherDimension(int dim) {
  PetscInt n = 0;
  char **names = nullptr, **values = nullptr;
  if (PetscOptionsLeftGet(nullptr, &n, &names, &values)) return;
  std::string error;
  for (PetscInt i = 0; i < n && error.empty(); ++i) {
    const std::string name = names[i], value = values[i] ? values[i] : "";
    if (name.rfind("gimp_", 0) != 0 || !findOption(name)) continue;
    const Feature *f = featureOf(name, value);
    if (!f) f = featureOf(name);
    if (f && !(f->dims & (dim == 2 ? In2D : In3D)))
      error = "option -" + name + " " + value + ": not available with -gimp_dim " +
              std::to_string(dim) + " (" + f->what + "): " + f->why;
  }
  (void)PetscOptionsLeftRestore(nullptr, &n, &names, &values);
  if (!error.empty()) throw InputError(error);
}

} // namespace gimp::input
