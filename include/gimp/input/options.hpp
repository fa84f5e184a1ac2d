// Every option of a scene, declared once (src/input/option_table*.cpp): its name, kind, the
// dimensions it exists in, unit, default, values, check and help text. The same declarations
// drive the reader (Options: -help lists them, a value is checked as declared, an option of the
// other dimension is refused with its reason), the bad-input pre-check of every value
// (validate.cpp) and the option list of docs/options.md (`gimp -gimp_options_markdown`; a test
// fails when the two differ). What exists in one dimension only is the feature table below: one
// place that says which features exist in which dimension and why, and every refusal comes from
// it.
#pragma once

#include "gimp/input/scene.hpp"

#include <string>
#include <vector>

namespace gimp::input {

enum class Kind { Real, Int, Bool, Word, Choice, Reals, Ramp };

/// The dimensions an option, a value or a feature exists in.
enum Dims : unsigned { In2D = 1, In3D = 2, InBoth = 3 };

/// A value's range (applied when the option is given): above lo, at least lo, or within
/// [lo, hi] (either end open); integer: a whole number.
struct Check {
  enum Op { None, Above, AtLeast, Within } op = None;
  double lo = 0, hi = 0;
  bool openLo = false, openHi = false, integer = false;
  /// "must be > 0", "must lie in [0, 1)", "must be an integer from 2 to 16", ... ("": None).
  std::string rule() const;
  bool holds(double v) const;
};

struct OptionSpec {
  const char *name; // without the dash; a family member's index is K, a second index J
  Kind kind;
  const char *unit;       // SI unit ("" for numbers without one, words and choices)
  const char *def;        // the default, as docs/options.md shows it ("" none, "(required)")
  const char *valuesIn2D; // Reals: the values in 2D ("x0,y0,x1,y1"; groups end ",..."); Choice:
                          // the choices "a|b|c" (those of one dimension only: the feature table)
  const char *valuesIn3D; // the same in 3D (nullptr: as in 2D)
  Check check;
  const char *help;
  /// The values' description in dimension D (valuesIn2D or valuesIn3D).
  const char *values(int dim) const { return dim == 3 && valuesIn3D ? valuesIn3D : valuesIn2D; }
};

/// Something that exists in some dimensions only: the options (or "option=value" choices) that
/// ask for it and why it is not in the others.
struct Feature {
  const char *what;
  Dims dims;
  std::vector<const char *> options;
  const char *why;
};

/// Every option, in the order of docs/options.md.
const std::vector<OptionSpec> &optionTable();
/// What exists in one dimension only.
const std::vector<Feature> &featureTable();

/// The declaration of option `name` (without the dash; family indices as digits: gimp_body3_box),
/// or null.
const OptionSpec *findOption(const std::string &name);
/// The dimensions option `name` (with `value`, for a choice) exists in, from the feature table.
Dims dimsOf(const std::string &name, const std::string &value = "");
/// The feature that option `name` (with `value`) belongs to, or null when it exists in both.
const Feature *featureOf(const std::string &name, const std::string &value = "");

/// The option table as Markdown: the list in docs/options.md.
std::string optionsMarkdown();

/// A PETSc error while reading an option (a value that is not a number, ...): readScene returns
/// its code, and readOptionsOneLine turns PETSc's message into one line.
struct OptionsReadError {
  PetscErrorCode code;
};

/// Reads the options of a scene of dimension `dim` from the PETSc options database, each by its
/// declaration: -help lists what is read, a value outside its check or of an option of the other
/// dimension is one InputError line. Collective (PETSc's option reading is).
class Options {
public:
  Options(MPI_Comm comm, int dim, bool help) : comm_(comm), dim_(dim), help_(help) {}
  bool help() const { return help_; }
  int dim() const { return dim_; }
  MPI_Comm comm() const { return comm_; }
  /// Whether the option was given.
  bool given(const std::string &name) const;
  /// The value option `name` was given with, as written, for an error line ("(given)" for a name
  /// given without a value).
  std::string givenValue(const std::string &name) const;
  double real(const std::string &name, double def, bool *given = nullptr) const;
  PetscInt integer(const std::string &name, PetscInt def, bool *given = nullptr) const;
  bool flag(const std::string &name, bool def, bool *given = nullptr) const;
  std::string word(const std::string &name, const std::string &def, bool *given = nullptr) const;
  /// One of the option's choices in this dimension (the default when not given).
  std::string choice(const std::string &name, const std::string &def, bool *given = nullptr) const;
  /// The option's values, as many as declared for this dimension (a list of groups: a whole
  /// number of them); empty when not given, or when `required` an error naming what it needs.
  std::vector<double> reals(const std::string &name, bool required = false) const;
  /// A table t0,f0,t1,f1,... with strictly increasing times (empty when not given).
  Ramp ramp(const std::string &name) const;
  /// Throw the one-line error for option `name` with `value`: `valid` says what would be.
  [[noreturn]] static void bad(const std::string &name, const std::string &value,
                               const std::string &valid);
  /// Refuse an option given without what it acts with.
  void needs(bool has, const std::string &name, const std::string &what) const;

private:
  /// The declaration, refused first when the option was given in a dimension it does not exist
  /// in.
  const OptionSpec &spec(const std::string &name) const;
  /// The check of a given numeric value.
  void check(const std::string &name, const OptionSpec &s, double v) const;

  MPI_Comm comm_;
  int dim_;
  bool help_;
};

/// "v0,v1,..." as written in error messages.
std::string fmtList(const double *v, size_t n);

} // namespace gimp::input
