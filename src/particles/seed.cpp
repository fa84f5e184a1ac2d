// Seeding: each body's cells filled with particles at the body's density.
#include "gimp/particles/seed.hpp"

#include "gimp/geometry/cut_cell.hpp"
#include <limits>
#include <string>

#include <algorithm>
#include <cmath>
#include <vector>

namespace gimp {

template <> PetscInt64 bodyIdSlots<2>(const Lattice<2> &g);

namespace {

/// Whether the square particle (x, y, half-size l) of body b has an edge on the face.
bool onFace(const Scene<2> &sc, const Face<2> &f, int b, double x, double y, const double *l,
            double tol) {
  if (f.body != b) return false;
  const BoxOf<2> &box = sc.bodies[b].box;
  const int a = f.axis();
  const double at[2] = {x, y};
  const double edge = at[a] + f.normal() * l[a];
  const double target = f.normal() > 0 ? box[2 + a] : box[a];
  return std::fabs(edge - target) <= tol && f.inRange(at);
}

struct Seed {
  double x, y;
  double v[2] = {0, 0}; // a particle file's velocity, if it gives one
  double l[2];          // half-sizes
  double area; // the part of the square in the body (the whole square unless a hole cuts it)
  double cx0, cx1, cy0, cy1; // corners from the sub-cell lattice: neighbours share them exactly
  PetscInt64 id;
  int body;
};

/// Whether the seed's square keeps a part in the body. A square that the body's edge or a hole
/// cuts becomes that part (area, centroid, the rectangle of its second moments; its corners
/// that rectangle's). A rectangle body keeps a square by its centre (its sides lie on the
/// particle lattice in every scene it was made for); ellipses and polygons cut it.
bool cutByShape(const Body<2> &body, Seed &s) {
  const double w = s.cx1 - s.cx0, h = s.cy1 - s.cy0;
  const double xc = 0.5 * (s.cx0 + s.cx1), yc = 0.5 * (s.cy0 + s.cy1);
  std::array<double, 5> mom = cut::centredRectangleMoments(w, h);
  bool cut = false;
  if (body.shape.kind == Shape::Kind::Rectangle && body.added.empty()) {
    const BoxOf<2> &box = body.box;
    if (s.x < box[0] || s.x > box[2] || s.y < box[1] || s.y > box[3]) return false;
  } else {
    const auto in = body.unionMomentsIn(s.cx0, s.cy0, s.cx1, s.cy1, xc, yc);
    if (in[0] <= 1e-13 * w * h) return false;
    if (std::fabs(in[0] - w * h) > 1e-12 * w * h) { // the edge crosses the square
      mom = in;
      cut = true;
    }
  }
  for (const Hole &c : body.holes) {
    const double nx = std::clamp(c.cx, s.cx0, s.cx1), ny = std::clamp(c.cy, s.cy0, s.cy1);
    const double fx = std::max(std::fabs(s.cx0 - c.cx), std::fabs(s.cx1 - c.cx));
    const double fy = std::max(std::fabs(s.cy0 - c.cy), std::fabs(s.cy1 - c.cy));
    if (std::hypot(nx - c.cx, ny - c.cy) >= c.r) continue; // the hole misses the square
    if (std::hypot(fx, fy) <= c.r) return false;           // the hole holds the whole square
    const auto d =
        cut::rectDiskMoments(-0.5 * w, -0.5 * h, 0.5 * w, 0.5 * h, c.cx - xc, c.cy - yc, c.r);
    for (int i = 0; i < 5; ++i)
      mom[i] -= d[i];
    cut = true;
  }
  for (const Shape &hole : body.shapeHoles) {
    const auto d = hole.momentsIn(s.cx0, s.cy0, s.cx1, s.cy1, xc, yc);
    if (d[0] <= 0) continue;
    for (int i = 0; i < 5; ++i)
      mom[i] -= d[i];
    cut = true;
  }
  if (!cut) return true;
  const cut::Moments m = cut::fromRaw(mom, xc, yc, w * h);
  if (m.A <= 0) return false;
  const double half[2] = {0.5 * w, 0.5 * h};
  s.x = m.cx;
  s.y = m.cy;
  s.area = m.A;
  cut::equivalentRectangle(m, s.l);
  // A sliver's domain keeps a quarter of the square's half-size each way (its volume stays the
  // cut's area): a domain much thinner than its cell acts like a material point across the grid
  // line it straddles, the weight of the node beyond falls linearly instead of quadratically as
  // it leaves that node's support, and the tiny nodal mass against the weight's gradient gives a
  // frequency of about c / sqrt(h l) that the time step does not resolve.
  for (int a = 0; a < 2; ++a)
    s.l[a] = std::max(s.l[a], cut::kMinSliverFraction * half[a]);
  s.cx0 = s.x - s.l[0];
  s.cx1 = s.x + s.l[0];
  s.cy0 = s.y - s.l[1];
  s.cy1 = s.y + s.l[1];
  return true;
}

/// The particles of body b read from its particle file, as they are, each on the rank of its
/// point (slots: the ids a body has).
void fileSeeds(const Body<2> &body, size_t b, PetscInt64 slots, const Grid<2> &g, PetscMPIInt rank,
               std::vector<Seed> &seeds) {
  const std::vector<FileParticle<2>> &ps = body.fromFile.particles;
  if (static_cast<PetscInt64>(ps.size()) > slots) // the same on every rank
    throw InputError("option -gimp_body" + std::to_string(b) + "_file " + body.file + ": " +
                     std::to_string(ps.size()) + " particles, more than the " +
                     std::to_string(slots) + " ids a body has on this grid");
  for (size_t i = 0; i < ps.size(); ++i) {
    const FileParticle<2> &f = ps[i];
    if (g.ownerOf(f.x[0], f.x[1]) != rank) continue;
    Seed s{f.x[0],
           f.x[1],
           {f.v[0], f.v[1]},
           {f.l[0], f.l[1]},
           f.size,
           f.x[0] - f.l[0],
           f.x[0] + f.l[0],
           f.x[1] - f.l[1],
           f.x[1] + f.l[1],
           static_cast<PetscInt64>(b) * slots + static_cast<PetscInt64>(i),
           static_cast<int>(b)};
    seeds.push_back(s);
  }
}

/// The particles per cell of the body's cell from (cx0, cy0) of side h: holePpc where a hole
/// (widened by band) reaches into the cell without holding all of it, else ppc.
int cellPpc(const Body<2> &body, double cx0, double cy0, double h, double band) {
  int ppc = body.ppc;
  for (const Hole &c : body.holes) {
    // Nearest and farthest points of the cell from the hole centre.
    const double nx = std::clamp(c.cx, cx0, cx0 + h), ny = std::clamp(c.cy, cy0, cy0 + h);
    const double dmin = std::hypot(nx - c.cx, ny - c.cy);
    const double fx = std::max(std::fabs(cx0 - c.cx), std::fabs(cx0 + h - c.cx));
    const double fy = std::max(std::fabs(cy0 - c.cy), std::fabs(cy0 + h - c.cy));
    if (dmin <= c.r + band && std::hypot(fx, fy) >= c.r) ppc = body.holePpc;
  }
  return ppc;
}

/// Body b's particles on level q: its leaf cells there whose centre lies in this rank's level-0
/// cells, cut into n x n squares whose centres lie in the body (maxCells: the most cells of a
/// level, for the ids).
void levelSeeds(const Scene<2> &sc, const Grid<2> &g, PetscMPIInt rank, size_t b, int q,
                PetscInt64 maxCells, std::vector<Seed> &seeds) {
  const Body<2> &body = sc.bodies[b];
  const int K = static_cast<int>(g.levels.size());
  const Level<2> &L = g.levels[q];
  const double h = L.h;
  const double band = body.holeBand > 0 ? body.holeBand : h;
  const PetscInt i0 =
      std::max<PetscInt>(0, static_cast<PetscInt>(std::floor((body.box[0] - L.box[0]) / h)));
  const PetscInt j0 =
      std::max<PetscInt>(0, static_cast<PetscInt>(std::floor((body.box[1] - L.box[1]) / h)));
  const PetscInt i1 = std::min<PetscInt>(
      L.n[0] - 1, static_cast<PetscInt>(std::ceil((body.box[2] - L.box[0]) / h)));
  const PetscInt j1 = std::min<PetscInt>(
      L.n[1] - 1, static_cast<PetscInt>(std::ceil((body.box[3] - L.box[1]) / h)));
  for (PetscInt j = j0; j < j1; ++j)
    for (PetscInt i = i0; i < i1; ++i) {
      const double cx0 = L.box[0] + i * h, cy0 = L.box[1] + j * h;
      if (g.leafLevelAt(cx0 + 0.5 * h, cy0 + 0.5 * h) != q) continue;
      if (g.ownerOf(cx0 + 0.5 * h, cy0 + 0.5 * h) != rank) continue;
      if (cx0 + h <= body.box[0] || cx0 >= body.box[2] || cy0 + h <= body.box[1] ||
          cy0 >= body.box[3])
        continue;
      const int ppc = cellPpc(body, cx0, cy0, h, band);
      const int n = static_cast<int>(std::lround(std::sqrt(static_cast<double>(ppc))));
      const double d = h / n;
      const PetscInt64 cell = static_cast<PetscInt64>(j) * L.n[0] + i;
      for (int b2 = 0; b2 < n; ++b2)
        for (int a = 0; a < n; ++a) {
          const PetscInt64 nx = static_cast<PetscInt64>(i) * n + a,
                           ny = static_cast<PetscInt64>(j) * n + b2;
          Seed s{cx0 + (a + 0.5) * d,
                 cy0 + (b2 + 0.5) * d,
                 {0.0, 0.0},
                 {0.5 * d, 0.5 * d},
                 d * d,
                 L.box[0] + nx * d,
                 L.box[0] + (nx + 1) * d,
                 L.box[1] + ny * d,
                 L.box[1] + (ny + 1) * d,
                 // Unique and independent of the rank count: body, level, cell, sub-cell.
                 (((static_cast<PetscInt64>(b) * K + q) * maxCells + cell) * 64 + b2) * 64 + a,
                 static_cast<int>(b)};
          if (sc.cutCells ? cutByShape(body, s) : body.inside(s.x, s.y)) seeds.push_back(s);
        }
    }
}

/// The particles this rank seeds: the leaf cells of every level whose centre lies in its
/// level-0 cells, cut into n x n squares whose centres lie in a body.
std::vector<Seed> collectSeeds(const Scene<2> &sc, const Grid<2> &g, PetscMPIInt rank) {
  std::vector<Seed> seeds;
  const int K = static_cast<int>(g.levels.size());
  PetscInt64 maxCells = 0;
  for (const Level<2> &L : g.levels)
    maxCells = std::max<PetscInt64>(maxCells, static_cast<PetscInt64>(L.n[0]) * L.n[1]);
  // Leaf cells of every level: a body's particles take the size of the finest cell there.
  // The rank owning the level-0 cell of a leaf cell's centre seeds it.
  const PetscInt64 slots = bodyIdSlots<2>(g);
  for (size_t b = 0; b < sc.bodies.size(); ++b) {
    const Body<2> &body = sc.bodies[b];
    if (!body.file.empty()) { // the file's particles as they are, each on the rank of its point
      fileSeeds(body, b, slots, g, rank, seeds);
      continue;
    }
    for (int q = 0; q < K; ++q)
      levelSeeds(sc, g, rank, b, q, maxCells, seeds);
  }
  return seeds;
}

} // namespace

template <> PetscInt64 bodyIdSlots<2>(const Lattice<2> &g) {
  PetscInt64 cells = 0;
  for (const Level<2> &L : g.levels)
    cells = std::max<PetscInt64>(cells, static_cast<PetscInt64>(L.n[0]) * L.n[1]);
  return static_cast<PetscInt64>(g.levels.size()) * cells * 64 * 64;
}

template <> PetscInt64 bodyIdSlots<3>(const Lattice<3> &) {
  return PetscInt64{1} << 40;
}

PetscErrorCode LoadConflict::agree(MPI_Comm comm,
                                   const std::vector<std::string> &shapeOptions) const {
  PetscInt64 mine = code < 0 ? std::numeric_limits<PetscInt64>::max() : code, all = mine;
  PetscCallMPI(MPI_Allreduce(&mine, &all, 1, MPI_INT64_T, MPI_MIN, comm));
  int overlapping = 0;
  PetscCallMPI(MPI_Allreduce(&overlap, &overlapping, 1, MPI_INT, MPI_MAX, comm));
  if (all == std::numeric_limits<PetscInt64>::max()) {
    if (overlapping > 0)
      throw InputError("option -gimp_body" + std::to_string(overlapping) + "_" +
                       shapeOptions[static_cast<size_t>(overlapping)] +
                       ": the body overlaps an earlier body (a particle centre lies in both)");
    return PETSC_SUCCESS;
  }
  const bool traction = (all >> 40) == 0;
  const PetscInt64 second = (all >> 20) & 0xfffff, first = all & 0xfffff;
  const std::string name = traction ? "gimp_traction" : "gimp_dbc";
  throw InputError("option -" + name + std::to_string(second) +
                   "_side: particles on it also lie on -" + name + std::to_string(first) +
                   "'s, on the same axis; a particle carries one " +
                   (traction ? "traction" : "penalty condition") +
                   " per axis (a body one particle thick loaded on both sides, or overlapping "
                   "ranges): make the body thicker or the ranges disjoint");
}

template <>
PetscErrorCode seedParticles<2>(const Scene<2> &sc, const Grid<2> &g, DM sw,
                                LoadConflict &conflict) {
  PetscMPIInt rank = 0;
  PetscCallMPI(MPI_Comm_rank(PetscObjectComm(reinterpret_cast<PetscObject>(sw)), &rank));
  const std::vector<Seed> seeds = collectSeeds(sc, g, rank);
  PetscCall(DMSwarmSetLocalSizes(sw, static_cast<PetscInt>(seeds.size()), 16));
  ParticleView<2> p;
  PetscCall(p.get(sw));
  const double tol = 1e-9 * g.hMin();
  for (PetscInt k = 0; k < p.n; ++k) {
    const Seed &s = seeds[k];
    const Body<2> &body = sc.bodies[s.body];
    p.x[2 * k] = p.X0[2 * k] = s.x;
    p.x[2 * k + 1] = p.X0[2 * k + 1] = s.y;
    double vx = body.velocity[0], vy = body.velocity[1];
    if (body.fromFile.hasVelocity) {
      vx = s.v[0];
      vy = s.v[1];
    }
    if (body.sineProfile) {
      const double f = std::sin(body.wavenumber * (s.x - body.box[0]));
      vx *= f;
      vy *= f;
    }
    // A rigid rotation omega x (X - c) about the box's centre c.
    vx -= body.spin * (s.y - 0.5 * (body.box[1] + body.box[3]));
    vy += body.spin * (s.x - 0.5 * (body.box[0] + body.box[2]));
    p.v[2 * k] = vx;
    p.v[2 * k + 1] = vy;
    if (p.B) std::fill(&p.B[4 * k], &p.B[4 * k] + 4, 0.0); // APIC's affine moment: none yet
    p.V0[k] = p.V[k] = s.area * sc.material.thickness;
    p.m[k] = body.material.rho * p.V0[k];
    for (int a = 0; a < 2; ++a)
      p.l[2 * k + a] = p.l0[2 * k + a] = s.l[a];
    if (p.hasCorners) {
      const double c[8] = {s.cx0, s.cy0, s.cx1, s.cy0, s.cx1, s.cy1, s.cx0, s.cy1};
      std::copy(c, c + 8, &p.corners[8 * k]);
    }
    p.F[4 * k] = p.F[4 * k + 3] = 1.0;
    p.F[4 * k + 1] = p.F[4 * k + 2] = 0.0;
    for (int c = 0; c < kStress<2>; ++c)
      p.s[kStress<2> * k + c] = 0.0;
    p.szz[k] = 0.0;
    if (p.eps) p.eps[2 * k] = p.eps[2 * k + 1] = 0.0;
    if (p.us) p.us[2 * k] = p.us[2 * k + 1] = 0.0;
    p.id[k] = s.id;
    p.rank[k] = rank;
    if (p.rate) p.rate[k] = -1; // -gimp_multirate: no rate class yet
    if (p.trac) {               // (the fields exist with tractions or penalty conditions)
      p.trac[2 * k] = p.trac[2 * k + 1] = -1;
      p.dbc[2 * k] = p.dbc[2 * k + 1] = -1;
    }
    for (size_t t = 0; t < sc.tractions.size(); ++t)
      if (onFace(sc, sc.tractions[t], s.body, s.x, s.y, s.l, tol)) {
        PetscInt &slot = p.trac[2 * k + sc.tractions[t].axis()];
        if (slot >= 0) conflict.note(0, slot, static_cast<PetscInt64>(t));
        slot = static_cast<PetscInt>(t);
      }
    for (size_t t = 0; t < sc.dbcs.size(); ++t)
      if (onFace(sc, sc.dbcs[t], s.body, s.x, s.y, s.l, tol)) {
        PetscInt &slot = p.dbc[2 * k + sc.dbcs[t].axis()];
        if (slot >= 0) conflict.note(1, slot, static_cast<PetscInt64>(t));
        slot = static_cast<PetscInt>(t);
      }
  }
  PetscCall(p.restore(sw));
  return PETSC_SUCCESS;
}

} // namespace gimp
