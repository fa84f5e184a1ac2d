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

/// The header's columns by name, or why they cannot be used.
std::string readHeader(const std::string &line, std::map<std::string, size_t> &at, size_t &count) {
  const std::vector<std::string> cols = split(line);
  count = cols.size();
  const char *ignored[] = {"id", "sxx", "syy", "sxy", "szz"};
  for (size_t c = 0; c < cols.size(); ++c) {
    bool known = false;
    for (const char *k : {"x", "y", "lx", "ly", "V", "vx", "vy"})
      known |= cols[c] == k;
    bool skip = false;
    for (const char *k : ignored)
      skip |= cols[c] == k;
    if (!known && !skip)
      return "unknown column '" + cols[c] + "' (columns: x, y, lx, ly, V, vx, vy)";
    if (at.count(cols[c])) return "column '" + cols[c] + "' appears twice";
    at[cols[c]] = c;
  }
  if (!at.count("x") || !at.count("y")) return "needs the columns x and y";
  if (at.count("lx") != at.count("ly")) return "needs both lx and ly, or neither";
  if (at.count("vx") != at.count("vy")) return "needs both vx and vy, or neither";
  if (!at.count("lx") && !at.count("V")) return "needs lx, ly (half-sizes) or V (volume)";
  return "";
}

/// One data row to a particle, or why it cannot be one (`where`: "line N").
std::string readRow(const std::vector<std::string> &f, std::map<std::string, size_t> &at,
                    double thickness, bool hasVelocity, const std::string &where, FileParticle &p) {
  std::vector<double> v(f.size());
  for (size_t c = 0; c < f.size(); ++c) {
    char *end = nullptr;
    v[c] = std::strtod(f[c].c_str(), &end);
    if (f[c].empty() || *end != '\0') return where + ": '" + f[c] + "' is not a number";
    if (!std::isfinite(v[c])) return where + ": the values must be finite numbers";
  }
  p.x = v[at["x"]];
  p.y = v[at["y"]];
  if (at.count("V")) {
    if (!(v[at["V"]] > 0)) return where + ": V must be > 0";
    p.area = v[at["V"]] / thickness;
  }
  if (at.count("lx")) {
    p.lx = v[at["lx"]];
    p.ly = v[at["ly"]];
    if (!(p.lx > 0) || !(p.ly > 0)) return where + ": lx and ly must be > 0";
    if (!at.count("V")) p.area = 4.0 * p.lx * p.ly;
  } else {
    p.lx = p.ly = 0.5 * std::sqrt(p.area);
  }
  // A size so small that its area or a half-size is not a normal double (below 2.2e-308)
  // would give the particle no mass, and the run would fail later for another reason.
  if (!std::isnormal(p.area) || !std::isnormal(p.lx) || !std::isnormal(p.ly))
    return where + ": the particle's size is too small to represent (its area " +
           formatNumber(p.area) + " m^2 or a half-size is below 2.2e-308)";
  if (hasVelocity) {
    p.vx = v[at["vx"]];
    p.vy = v[at["vy"]];
  }
  return "";
}

/// Whether the centre of `a` lies inside the domain of `b` by more than round-off (a
/// billionth of b's half-size and the coordinates' own round-off).
bool centreInside(const FileParticle &a, const FileParticle &b) {
  auto within = [](double ca, double cb, double lb) {
    return std::fabs(ca - cb) < lb - 1e-9 * lb - 1e-15 * (std::fabs(ca) + std::fabs(cb) + lb);
  };
  return within(a.x, b.x, b.lx) && within(a.y, b.y, b.ly);
}

/// Two particles that claim the same material: the centre of one inside the domain of the
/// other (the same particle twice, as in a file appended to itself, or domains that overlap by
/// more than half their width along both axes), or "". The domains of cut-cell particles (a
/// rectangle of the cut area around its centroid, as gimp's own dumps hold them) may overlap a
/// little: that is allowed. Particles are binned in cells of the largest domain's width, so only
/// those of neighbouring cells are compared.
std::string overlapOf(const std::vector<FileParticle> &ps, const std::vector<size_t> &lines) {
  double width = 0;
  for (const FileParticle &p : ps)
    width = std::max(width, 2.0 * std::max(p.lx, p.ly));
  auto cellOf = [&](double x) {
    return static_cast<std::int64_t>(std::clamp(std::floor(x / width), -1e15, 1e15));
  };
  auto key = [](std::int64_t i, std::int64_t j) {
    return static_cast<std::uint64_t>(i) * 0x9E3779B97F4A7C15ULL ^ static_cast<std::uint64_t>(j);
  };
  std::unordered_map<std::uint64_t, std::vector<size_t>> cells;
  for (size_t i = 0; i < ps.size(); ++i) {
    const FileParticle &a = ps[i];
    const std::int64_t ci = cellOf(a.x), cj = cellOf(a.y);
    size_t first = i;
    for (std::int64_t di = -1; di <= 1; ++di)
      for (std::int64_t dj = -1; dj <= 1; ++dj) {
        const auto cell = cells.find(key(ci + di, cj + dj));
        if (cell == cells.end()) continue;
        for (const size_t j : cell->second) {
          const FileParticle &b = ps[j];
          if (j < first && (centreInside(a, b) || centreInside(b, a))) first = j;
        }
      }
    if (first < i)
      return "the particles of lines " + std::to_string(lines[first]) + " and " +
             std::to_string(lines[i]) + " (at " + formatNumber(ps[first].x) + "," +
             formatNumber(ps[first].y) + " and " + formatNumber(a.x) + "," + formatNumber(a.y) +
             ") overlap: the centre of one lies in the other's domain (is a particle in the file "
             "twice?)";
    cells[key(ci, cj)].push_back(i);
  }
  return "";
}

/// Parses the file; returns "" or why it cannot be used.
std::string parse(const std::string &path, double thickness, ParticleFile &out) {
  std::string text;
  const std::string unreadable = readText(path, text);
  if (!unreadable.empty()) return unreadable;
  std::istringstream in(text);
  std::string line;
  if (!std::getline(in, line)) return "the file is empty (a header line x,y,... is needed)";
  std::map<std::string, size_t> at;
  size_t columns = 0;
  const std::string header = readHeader(line, at, columns);
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
    FileParticle p;
    const std::string why = readRow(f, at, thickness, out.hasVelocity, where, p);
    if (!why.empty()) return why;
    out.particles.push_back(p);
    lines.push_back(row);
  }
  if (out.particles.empty()) return "holds no particle";
  return overlapOf(out.particles, lines);
}

} // namespace

PetscErrorCode readParticleFile(MPI_Comm comm, const std::string &opt, const std::string &path,
                                double thickness, ParticleFile &out) {
  PetscMPIInt rank = 0;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  std::string why;
  out = ParticleFile{};
  if (rank == 0) why = parse(path, thickness, out);
  // Every rank learns the same outcome: the error text, then the particles.
  long long sizes[3] = {static_cast<long long>(why.size()),
                        static_cast<long long>(out.particles.size()), out.hasVelocity ? 1 : 0};
  PetscCallMPI(MPI_Bcast(sizes, 3, MPI_LONG_LONG, 0, comm));
  why.resize(static_cast<size_t>(sizes[0]));
  if (sizes[0]) PetscCallMPI(MPI_Bcast(why.data(), static_cast<int>(sizes[0]), MPI_CHAR, 0, comm));
  if (!why.empty()) throw InputError("option " + opt + " " + path + ": " + why);
  out.particles.resize(static_cast<size_t>(sizes[1]));
  out.hasVelocity = sizes[2] != 0;
  static_assert(sizeof(FileParticle) == 7 * sizeof(double), "FileParticle is 7 doubles");
  PetscCallMPI(
      MPI_Bcast(out.particles.data(), static_cast<int>(7 * sizes[1]), MPI_DOUBLE, 0, comm));
  return PETSC_SUCCESS;
}

} // namespace gimp
