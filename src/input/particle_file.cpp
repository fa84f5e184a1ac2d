// Particle files (see include/gimp/input/particle_file.hpp).
#include "gimp/input/particle_file.hpp"
#include "gimp/core/errors.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <unordered_map>

namespace gimp {

namespace {

std::string trim(const std::string &s) {
  const size_t a = s.find_first_not_of(" \t\r"), b = s.find_last_not_of(" \t\r");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

std::vector<std::string> split(const std::string &line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string f;
  while (std::getline(ss, f, ','))
    out.push_back(trim(f));
  if (!line.empty() && line.back() == ',') out.push_back("");
  return out;
}

/// The whole file as text, or why it is not one: a NUL byte (binary, UTF-16) or a UTF-16
/// byte-order mark. A UTF-8 byte-order mark is dropped.
std::string readText(const std::string &path, std::string &text) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return "is a directory, not a file";
  std::ifstream in(path, std::ios::binary);
  if (!in) return "cannot open the file";
  std::ostringstream all;
  all << in.rdbuf();
  if (in.bad()) return "cannot read the file";
  text = all.str();
  if (text.compare(0, 2, "\xFF\xFE") == 0 || text.compare(0, 2, "\xFE\xFF") == 0)
    return "not a text CSV file (UTF-16; save it as UTF-8 or ASCII)";
  const size_t nul = text.find('\0');
  if (nul != std::string::npos)
    return "not a text CSV file (a NUL byte on line " +
           std::to_string(1 + std::count(text.begin(), text.begin() + nul, '\n')) + ")";
  if (text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);
  return "";
}

/// The names of a D-vector's columns: x, y, z with the prefix ("l": half-sizes, "v": velocity).
template <int D> std::vector<std::string> columnsOf(const std::string &prefix) {
  std::vector<std::string> out;
  for (int a = 0; a < D; ++a)
    out.push_back(prefix + "xyz"[a]);
  return out;
}

/// "x, y, z".
std::string commaList(const std::vector<std::string> &names) {
  std::string out;
  for (const std::string &k : names)
    out += (out.empty() ? "" : ", ") + k;
  return out;
}

/// "x and y", "x, y and z".
std::string inWords(const std::vector<std::string> &names) {
  std::string out;
  for (size_t i = 0; i < names.size(); ++i)
    out += (i == 0 ? "" : i + 1 == names.size() ? " and " : ", ") + names[i];
  return out;
}

/// "x,y" or "x,y,z" of a point.
template <int D> std::string pointText(const double *x) {
  std::string out;
  for (int a = 0; a < D; ++a)
    out += (a ? "," : "") + formatNumber(x[a]);
  return out;
}

/// The header's columns by name, or why they cannot be used.
template <int D>
std::string readHeader(const std::string &line, std::map<std::string, size_t> &at, size_t &count) {
  const std::vector<std::string> cols = split(line);
  const std::vector<std::string> xs = columnsOf<D>(""), ls = columnsOf<D>("l"),
                                 vs = columnsOf<D>("v");
  std::vector<std::string> known = xs;
  known.insert(known.end(), ls.begin(), ls.end());
  known.push_back("V");
  known.insert(known.end(), vs.begin(), vs.end());
  std::vector<std::string> ignored = {"id", "sxx", "syy", "sxy", "szz"};
  if (D == 3) ignored.insert(ignored.end(), {"syz", "sxz"});
  count = cols.size();
  for (size_t c = 0; c < cols.size(); ++c) {
    const bool isKnown = std::find(known.begin(), known.end(), cols[c]) != known.end();
    const bool skip = std::find(ignored.begin(), ignored.end(), cols[c]) != ignored.end();
    if (!isKnown && !skip)
      return "unknown column '" + cols[c] + "' (columns: " + commaList(known) + ")";
    if (at.count(cols[c])) return "column '" + cols[c] + "' appears twice";
    at[cols[c]] = c;
  }
  auto given = [&](const std::vector<std::string> &names) {
    size_t n = 0;
    for (const std::string &k : names)
      n += at.count(k);
    return n;
  };
  const std::string both = D == 2 ? "both " : "all of ", neither = D == 2 ? "neither" : "none";
  if (given(xs) < D) return "needs the columns " + inWords(xs);
  if (given(ls) % D) return "needs " + both + inWords(ls) + ", or " + neither;
  if (given(vs) % D) return "needs " + both + inWords(vs) + ", or " + neither;
  if (!given(ls) && !at.count("V")) return "needs " + commaList(ls) + " (half-sizes) or V (volume)";
  return "";
}

/// One data row to a particle, or why it cannot be one (`where`: "line N").
template <int D>
std::string readRow(const std::vector<std::string> &f, std::map<std::string, size_t> &at,
                    double thickness, bool hasVelocity, const std::string &where,
                    FileParticle<D> &p) {
  std::vector<double> v(f.size());
  for (size_t c = 0; c < f.size(); ++c) {
    char *end = nullptr;
    v[c] = std::strtod(f[c].c_str(), &end);
    if (f[c].empty() || *end != '\0') return where + ": '" + f[c] + "' is not a number";
    if (!std::isfinite(v[c])) return where + ": the values must be finite numbers";
  }
  const std::vector<std::string> xs = columnsOf<D>(""), ls = columnsOf<D>("l"),
                                 vs = columnsOf<D>("v");
  for (int a = 0; a < D; ++a)
    p.x[a] = v[at[xs[a]]];
  if (at.count("V")) {
    if (!(v[at["V"]] > 0)) return where + ": V must be > 0";
    p.size = v[at["V"]] / thickness;
  }
  if (at.count(ls[0])) {
    bool positive = true;
    for (int a = 0; a < D; ++a) {
      p.l[a] = v[at[ls[a]]];
      positive = positive && p.l[a] > 0;
    }
    if (!positive) return where + ": " + inWords(ls) + " must be > 0";
    if (!at.count("V")) {
      p.size = 2.0 * p.l[0];
      for (int a = 1; a < D; ++a)
        p.size *= 2.0 * p.l[a];
    }
  } else {
    const double side = D == 2 ? std::sqrt(p.size) : std::cbrt(p.size);
    for (int a = 0; a < D; ++a)
      p.l[a] = 0.5 * side;
  }
  // A size so small that its area (volume) or a half-size is not a normal double (below
  // 2.2e-308) would give the particle no mass, and the run would fail later for another reason.
  bool normal = std::isnormal(p.size);
  for (int a = 0; a < D; ++a)
    normal = normal && std::isnormal(p.l[a]);
  if (!normal)
    return where + ": the particle's size is too small to represent (its " +
           (D == 2 ? "area " : "volume ") + formatNumber(p.size) + (D == 2 ? " m^2" : " m^3") +
           " or a half-size is below 2.2e-308)";
  if (hasVelocity)
    for (int a = 0; a < D; ++a)
      p.v[a] = v[at[vs[a]]];
  return "";
}

/// Whether the centre of `a` lies inside the domain of `b` by more than round-off (a
/// billionth of b's half-size and the coordinates' own round-off).
template <int D> bool centreInside(const FileParticle<D> &a, const FileParticle<D> &b) {
  auto within = [](double ca, double cb, double lb) {
    return std::fabs(ca - cb) < lb - 1e-9 * lb - 1e-15 * (std::fabs(ca) + std::fabs(cb) + lb);
  };
  for (int q = 0; q < D; ++q)
    if (!within(a.x[q], b.x[q], b.l[q])) return false;
  return true;
}

/// Two particles that claim the same material: the centre of one inside the domain of the
/// other (the same particle twice, as in a file appended to itself, or domains that overlap by
/// more than half their width along every axis), or "". The domains of cut-cell particles (a
/// box of the cut's size around its centroid, as gimp's own dumps hold them) may overlap a
/// little: that is allowed. Particles are binned in cells of the largest domain's width, so only
/// those of neighbouring cells are compared.
template <int D>
std::string overlapOf(const std::vector<FileParticle<D>> &ps, const std::vector<size_t> &lines) {
  double width = 0;
  for (const FileParticle<D> &p : ps)
    for (int a = 0; a < D; ++a)
      width = std::max(width, 2.0 * p.l[a]);
  auto cellOf = [&](double x) {
    return static_cast<std::int64_t>(std::clamp(std::floor(x / width), -1e15, 1e15));
  };
  auto key = [](const std::int64_t *c) {
    std::uint64_t k = 0;
    for (int a = 0; a < D; ++a)
      k = k * 0x9E3779B97F4A7C15ULL ^ static_cast<std::uint64_t>(c[a]);
    return k;
  };
  std::unordered_map<std::uint64_t, std::vector<size_t>> cells;
  int neighbours = 1;
  for (int a = 0; a < D; ++a)
    neighbours *= 3;
  for (size_t i = 0; i < ps.size(); ++i) {
    const FileParticle<D> &a = ps[i];
    std::int64_t c[D];
    for (int q = 0; q < D; ++q)
      c[q] = cellOf(a.x[q]);
    size_t first = i;
    for (int m = 0; m < neighbours; ++m) {
      std::int64_t n[D];
      for (int q = 0, r = m; q < D; ++q, r /= 3)
        n[q] = c[q] + r % 3 - 1;
      const auto cell = cells.find(key(n));
      if (cell == cells.end()) continue;
      for (const size_t j : cell->second) {
        const FileParticle<D> &b = ps[j];
        if (j < first && (centreInside(a, b) || centreInside(b, a))) first = j;
      }
    }
    if (first < i)
      return "the particles of lines " + std::to_string(lines[first]) + " and " +
             std::to_string(lines[i]) + " (at " + pointText<D>(ps[first].x) + " and " +
             pointText<D>(a.x) +
             ") overlap: the centre of one lies in the other's domain (is a particle in the file "
             "twice?)";
    cells[key(c)].push_back(i);
  }
  return "";
}

/// Parses the file; returns "" or why it cannot be used.
template <int D>
std::string parse(const std::string &path, double thickness, ParticleFile<D> &out) {
  std::string text;
  const std::string unreadable = readText(path, text);
  if (!unreadable.empty()) return unreadable;
  std::istringstream in(text);
  std::string line;
  if (!std::getline(in, line))
    return std::string("the file is empty (a header line ") + (D == 2 ? "x,y" : "x,y,z") +
           ",... is needed)";
  std::map<std::string, size_t> at;
  size_t columns = 0;
  const std::string header = readHeader<D>(line, at, columns);
  if (!header.empty()) return header;
  out.hasVelocity = at.count("vx") > 0;
  std::vector<size_t> lines; // the line of each particle
  for (size_t row = 2; std::getline(in, line); ++row) {
    if (trim(line).empty()) continue;
    const std::vector<std::string> f = split(line);
    const std::string where = "line " + std::to_string(row);
    if (f.size() != columns)
      return where + " has " + std::to_string(f.size()) + " values for " + std::to_string(columns) +
             " columns";
    FileParticle<D> p;
    const std::string why = readRow<D>(f, at, thickness, out.hasVelocity, where, p);
    if (!why.empty()) return why;
    out.particles.push_back(p);
    lines.push_back(row);
  }
  if (out.particles.empty()) return "holds no particle";
  return overlapOf<D>(out.particles, lines);
}

} // namespace

template <int D>
PetscErrorCode readParticleFile(MPI_Comm comm, const std::string &opt, const std::string &path,
                                double thickness, ParticleFile<D> &out) {
  PetscMPIInt rank = 0;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  std::string why;
  out = ParticleFile<D>{};
  if (rank == 0) why = parse<D>(path, thickness, out);
  // Every rank learns the same outcome: the error text, then the particles.
  long long sizes[3] = {static_cast<long long>(why.size()),
                        static_cast<long long>(out.particles.size()), out.hasVelocity ? 1 : 0};
  PetscCallMPI(MPI_Bcast(sizes, 3, MPI_LONG_LONG, 0, comm));
  why.resize(static_cast<size_t>(sizes[0]));
  if (sizes[0]) PetscCallMPI(MPI_Bcast(why.data(), static_cast<int>(sizes[0]), MPI_CHAR, 0, comm));
  if (!why.empty()) throw InputError("option " + opt + " " + path + ": " + why);
  out.particles.resize(static_cast<size_t>(sizes[1]));
  out.hasVelocity = sizes[2] != 0;
  constexpr int doubles = 3 * D + 1;
  static_assert(sizeof(FileParticle<D>) == doubles * sizeof(double), "FileParticle: doubles");
  PetscCallMPI(
      MPI_Bcast(out.particles.data(), static_cast<int>(doubles * sizes[1]), MPI_DOUBLE, 0, comm));
  return PETSC_SUCCESS;
}

template PetscErrorCode readParticleFile<2>(MPI_Comm, const std::string &, const std::string &,
                                            double, ParticleFile<2> &);
template PetscErrorCode readParticleFile<3>(MPI_Comm, const std::string &, const std::string &,
                                            double, ParticleFile<3> &);

} // namespace gimp
