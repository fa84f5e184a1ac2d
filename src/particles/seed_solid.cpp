// Seeding a 3D scene: n^3 particles per leaf cell, each cube cut to its part in a solid body
// (input/bodies.hpp; or kept by its centre without cut cells), and the faces of the bodies'
// boxes that each particle's faces lie on.
#include "gimp/particles/seed.hpp"

#include "gimp/geometry/cut_cell.hpp"
#include "gimp/geometry/cut_cell3d.hpp"
#include "gimp/grid/cpdi_cells.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

namespace gimp {

namespace {

/// The face condition (index into `faces`) that particle face (axis a, side n at coordinate
/// `at`) of body b lies on, or -1.
/// The part of a traction's face that a particle's face covers (the traction's loaded area).
double loaded(const Traction<3> &t, int a, const double *x, const double *l) {
  const int b1 = a == 0 ? 1 : 0, b2 = a == 2 ? 1 : 2;
  return t.loadedArea(x[b1] - l[b1], x[b1] + l[b1], x[b2] - l[b2], x[b2] + l[b2]);
}
double loaded(const DisplacementBC<3> &, int, const double *, const double *) {
  return 1.0;
}

/// The face condition (index into `faces`, of load kind `kind`) that particle face (axis a, side
/// n at coordinate `at`) of body b lies on, or -1; a second one on the same face is noted.
template <class Faces>
PetscInt faceCondition(const Faces &faces, int kind, const Body<3> &body, int b, int a, double n,
                       double at, const double *x, const double *l, double tol,
                       LoadConflict &conflict) {
  PetscInt found = -1;
  for (size_t q = 0; q < faces.size(); ++q) {
    const auto &f = faces[q];
    if (f.body != b || f.axis() != a || f.normal() != n) continue;
    const double plane = n > 0 ? body.box[3 + a] : body.box[a];
    if (!(std::fabs(at - plane) <= tol && f.inRange(x) && loaded(f, a, x, l) > 0)) continue;
    if (found >= 0)
      conflict.note(kind, found, static_cast<PetscInt64>(q));
    else
      found = static_cast<PetscInt>(q);
  }
  return found;
}

/// A particle to seed: centre, half-size, volume, id and body; its cube's low and high corner
/// coordinates from the level's sub-cell lattice, so neighbours share their corners exactly; the
/// particle file's velocity, for a file body's particle that has one (else the body's).
struct Seed {
  double x[3], l[3], V, lo[3], hi[3];
  PetscInt64 id;
  int body;
  const double *v = nullptr;
};

/// The particles of file body b that this rank owns (those whose centre its level-0 cells
/// hold), as the file gives them; overlap as collectSeeds's: the larger of b and another
/// (non-file) body index when a particle's centre lies in that body.
void fileSeeds(const Scene<3> &sc, const Grid<3> &grid, PetscMPIInt rank, size_t b,
               std::vector<Seed> &seeds, int &overlap) {
  const Body<3> &body = sc.bodies[b];
  const std::vector<FileParticle<3>> &ps = body.fromFile.particles;
  if (static_cast<PetscInt64>(ps.size()) > sc.idSlots) // the same on every rank
    throw InputError("option -gimp_body" + std::to_string(b) + "_file " + body.file + ": " +
                     std::to_string(ps.size()) + " particles, more than the " +
                     std::to_string(sc.idSlots) + " ids a body has");
  for (size_t i = 0; i < ps.size(); ++i) {
    const FileParticle<3> &f = ps[i];
    if (grid.ownerOf(f.x) != rank) continue;
    Seed s;
    for (int a = 0; a < 3; ++a) {
      s.x[a] = f.x[a];
      s.l[a] = f.l[a];
      s.lo[a] = f.x[a] - f.l[a];
      s.hi[a] = f.x[a] + f.l[a];
    }
    s.V = f.size;
    s.id = static_cast<PetscInt64>(b) * sc.idSlots + static_cast<PetscInt64>(i);
    s.body = static_cast<int>(b);
    if (body.fromFile.hasVelocity) s.v = f.v;
    for (size_t o = 0; o < sc.bodies.size(); ++o) // two file bodies are taken as given
      if (o != b && sc.bodies[o].file.empty() && sc.bodies[o].inside(s.x))
        overlap = std::max(overlap, static_cast<int>(std::max(o, b)));
    seeds.push_back(s);
  }
}

/// How a solid (a round body or a hole) meets the cube [lo, hi]: misses it, holds all of it, or
/// cuts it.
enum class Meets { Misses, Holds, Cuts };

/// The squared distances from a sphere's centre (a cylinder's axis) to the nearest and the
/// farthest point of the cube [lo, hi].
void distances2(const Solid &so, const double *lo, const double *hi, double &near2, double &far2) {
  near2 = far2 = 0;
  for (int a = 0; a < 3; ++a) {
    if (so.kind == Solid::Cylinder && a == so.axis) continue;
    const double n = std::clamp(so.c[a], lo[a], hi[a]) - so.c[a];
    const double f = std::max(std::fabs(lo[a] - so.c[a]), std::fabs(hi[a] - so.c[a]));
    near2 += n * n;
    far2 += f * f;
  }
}

Meets meets(const Solid &so, const double *lo, const double *hi) {
  if (so.kind == Solid::BoxHole) { // a box hole keeps or drops the cube by its centre
    double c[3];
    for (int a = 0; a < 3; ++a)
      c[a] = 0.5 * (lo[a] + hi[a]);
    return so.strictlyContains(c) ? Meets::Holds : Meets::Misses;
  }
  double near2, far2;
  distances2(so, lo, hi, near2, far2);
  const bool along = so.kind == Solid::Cylinder;
  if (near2 >= so.r * so.r || (along && (hi[so.axis] <= so.lo || lo[so.axis] >= so.hi)))
    return Meets::Misses;
  if (far2 <= so.r * so.r && (!along || (lo[so.axis] >= so.lo && hi[so.axis] <= so.hi)))
    return Meets::Holds;
  return Meets::Cuts;
}

/// The raw moments of the part of the cube [lo, hi] in a sphere or cylinder, about the cube's
/// centre xc (so that the moments of a cube far from the origin keep their digits).
cut::Raw3 momentsIn(const Solid &so, const double *lo, const double *hi, const double *xc) {
  double l[3], h[3], o[3];
  for (int a = 0; a < 3; ++a) {
    l[a] = lo[a] - xc[a];
    h[a] = hi[a] - xc[a];
    o[a] = so.c[a] - xc[a];
  }
  if (so.kind == Solid::Sphere) return cut::boxBallMoments(l, h, o, so.r);
  const double z = xc[so.axis];
  return cut::boxCylinderMoments(l, h, so.axis, o, so.r, so.lo - z, so.hi - z);
}

/// A sphere or cylinder (not a box hole) about the point xc, for the geometry room.
cut::Round roundAbout(const Solid &so, const double *xc) {
  cut::Round r;
  r.ball = so.kind == Solid::Sphere;
  r.axis = so.axis;
  r.r = so.r;
  for (int a = 0; a < 3; ++a)
    r.c[a] = so.c[a] - xc[a];
  r.lo = so.lo - xc[so.axis];
  r.hi = so.hi - xc[so.axis];
  return r;
}

/// The raw moments about xc of the part of the cube [lo, hi] (sides w) in the round body (when
/// its surface cuts the cube; else the whole cube) and in none of the holes that cut it. One
/// curved surface: its closed form or slices; several: the slices of boxRoundsMoments, exact
/// where at most one of them is a disk along some axis, else each hole subtracted whole (their
/// common part twice).
cut::Raw3 cutMoments(const Solid *round, const std::vector<const Solid *> &holes, const double *lo,
                     const double *hi, const double *xc, const double *w) {
  if (holes.size() + (round ? 1 : 0) > 1) {
    double l[3], h[3];
    for (int a = 0; a < 3; ++a) {
      l[a] = lo[a] - xc[a];
      h[a] = hi[a] - xc[a];
    }
    std::vector<cut::Round> rs;
    for (const Solid *hole : holes)
      rs.push_back(roundAbout(*hole, xc));
    const cut::Round body = round ? roundAbout(*round, xc) : cut::Round{};
    cut::Raw3 m;
    if (cut::boxRoundsMoments(l, h, round ? &body : nullptr, rs, m)) return m;
  }
  cut::Raw3 mom = round ? momentsIn(*round, lo, hi, xc) : cut::centredBoxMoments(w);
  for (const Solid *hole : holes) {
    const cut::Raw3 d = momentsIn(*hole, lo, hi, xc);
    for (int i = 0; i < 7; ++i)
      mom[i] -= d[i];
  }
  return mom;
}

/// Whether the seed's cube keeps a part in the body. A cube that a sphere's or a cylinder's
/// surface cuts (the body's or a hole's) becomes that part: its volume, centroid and the box of
/// its second moments (its corners that box's). A box body and box holes keep or drop a cube by
/// its centre (their faces lie on the particle lattice in the scenes made for them).
bool cutBySolid(const Body<3> &body, Seed &s) {
  double w[3], xc[3], half[3];
  for (int a = 0; a < 3; ++a) {
    w[a] = s.hi[a] - s.lo[a];
    xc[a] = 0.5 * (s.lo[a] + s.hi[a]);
    half[a] = 0.5 * w[a];
  }
  const double whole = w[0] * w[1] * w[2];
  const Solid *round = nullptr; // the round body, where its surface cuts the cube
  if (body.kind == Body<3>::BoxShape) {
    for (int a = 0; a < 3; ++a)
      if (xc[a] < body.box[a] || xc[a] > body.box[3 + a]) return false;
  } else {
    const Meets m = meets(body.round, s.lo, s.hi);
    if (m == Meets::Misses) return false;
    if (m == Meets::Cuts) round = &body.round;
  }
  std::vector<const Solid *> holes; // the holes whose surface cuts the cube
  for (const Solid &hole : body.holes) {
    const Meets m = meets(hole, s.lo, s.hi);
    if (m == Meets::Holds) return false;
    if (m == Meets::Cuts) holes.push_back(&hole);
  }
  if (!round && holes.empty()) return true;
  const cut::Raw3 mom = cutMoments(round, holes, s.lo, s.hi, xc, w);
  const cut::Moments3 m = cut::fromRaw3(mom, xc, whole);
  if (m.V <= 0) return false;
  s.V = m.V;
  cut::equivalentBox(m, s.l, w);
  for (int a = 0; a < 3; ++a) { // a sliver keeps a quarter of the cube's half-size (seed.cpp)
    s.x[a] = m.c[a];
    s.l[a] = std::max(s.l[a], cut::kMinSliverFraction * half[a]);
    s.lo[a] = s.x[a] - s.l[a];
    s.hi[a] = s.x[a] + s.l[a];
  }
  return true;
}

/// The particles per cell of the body's cell [lo, hi]: holePpc where a spherical or cylindrical
/// hole (widened by band) reaches into the cell without holding all of it, else ppc.
int cellPpc(const Body<3> &body, const double *lo, const double *hi, double band) {
  for (const Solid &so : body.holes) {
    if (so.kind == Solid::BoxHole) continue;
    double near2, far2;
    distances2(so, lo, hi, near2, far2);
    if (near2 <= (so.r + band) * (so.r + band) && far2 >= so.r * so.r) return body.holePpc;
  }
  return body.ppc;
}

/// The particles this rank seeds: n^3 per leaf cell whose centre its own level-0 cells hold, each
/// cube cut to its part in a body (cutBySolid; without cut cells kept where its centre lies in
/// the body); overlap is the largest body index whose particle another body also holds.
std::vector<Seed> collectSeeds(const Scene<3> &sc, const Grid<3> &grid, PetscMPIInt rank,
                               int &overlap) {
  std::vector<Seed> seeds;
  // Every rank walks every leaf cell in the same order, so a particle's id does not depend on
  // the rank count; it keeps the cells whose centre its own level-0 cells hold. A first walk
  // counts the cells that meet a body's box, so that the seeds are stored once (growing the
  // vector copied it about twice over, a second of a 5-million-particle setup).
  const auto ownLeaf = [&](size_t k, const LatticeIndex<3> &c, double *centre) {
    const Level<3> &L = grid.levels[k];
    for (int a = 0; a < 3; ++a)
      centre[a] = grid.nodeCoordinate(static_cast<int>(k), a, c[a]) + 0.5 * L.h;
    return grid.leafLevelAt(centre) == static_cast<int>(k) && grid.ownerOf(centre) == rank;
  };
  size_t bound = 0;
  for (size_t k = 0; k < grid.levels.size(); ++k) {
    const Level<3> &L = grid.levels[k];
    std::array<PetscInt, 3> cells;
    for (int a = 0; a < 3; ++a)
      cells[a] = L.n[a] - 1;
    forEachIndex<3>(cells, [&](const LatticeIndex<3> &c) {
      double centre[3];
      if (!ownLeaf(k, c, centre)) return;
      for (const Body<3> &body : sc.bodies) {
        if (!body.file.empty()) continue; // (fileSeeds)
        bool meets = true;
        for (int a = 0; a < 3; ++a)
          meets = meets && centre[a] + 0.5 * L.h >= body.box[a] &&
                  centre[a] - 0.5 * L.h <= body.box[3 + a];
        if (meets) bound += static_cast<size_t>(body.ppc);
      }
    });
  }
  for (const Body<3> &body : sc.bodies)
    bound += body.fromFile.particles.size();
  seeds.reserve(bound);
  PetscInt64 cellBase = 0;
  for (size_t k = 0; k < grid.levels.size(); ++k) {
    const Level<3> &L = grid.levels[k];
    std::array<PetscInt, 3> cells;
    PetscInt64 nc = 1;
    for (int a = 0; a < 3; ++a) {
      cells[a] = L.n[a] - 1;
      nc *= cells[a];
    }
    forEachIndex<3>(cells, [&](const LatticeIndex<3> &c) {
      double centre[3];
      if (!ownLeaf(k, c, centre)) return;
      const PetscInt64 cell = cellBase + c[0] + cells[0] * (c[1] + cells[1] * c[2]);
      for (size_t b = 0; b < sc.bodies.size(); ++b) {
        const Body<3> &body = sc.bodies[b];
        if (!body.file.empty()) continue; // (fileSeeds)
        double lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
          lo[a] = centre[a] - 0.5 * L.h;
          hi[a] = lo[a] + L.h;
        }
        const int ppc = body.holePpc == body.ppc
                            ? body.ppc
                            : cellPpc(body, lo, hi, body.holeBand > 0 ? body.holeBand : L.h);
        const int n = static_cast<int>(std::lround(std::cbrt(static_cast<double>(ppc))));
        const int slots = std::max(body.ppc, body.holePpc); // ids per cell
        const double d = L.h / n;
        std::array<PetscInt, 3> sub = {n, n, n};
        forEachIndex<3>(sub, [&](const LatticeIndex<3> &q) {
          Seed s;
          for (int a = 0; a < 3; ++a) {
            s.x[a] = centre[a] - 0.5 * L.h + (q[a] + 0.5) * d;
            const double sub = static_cast<double>(c[a] * n + q[a]);
            s.lo[a] = L.box[a] + sub * d;
            s.hi[a] = L.box[a] + (sub + 1) * d;
          }
          s.l[0] = s.l[1] = s.l[2] = 0.5 * d;
          s.V = d * d * d;
          if (!(sc.cutCells ? cutBySolid(body, s) : body.inside(s.x))) return;
          for (size_t o = 0; o < b; ++o) // a point two bodies hold: counted, refused by setup
            if (sc.bodies[o].file.empty() && sc.bodies[o].inside(s.x))
              overlap = std::max(overlap, static_cast<int>(b));
          s.body = static_cast<int>(b);
          s.id =
              static_cast<PetscInt64>(b) * sc.idSlots + cell * slots + q[0] + n * (q[1] + n * q[2]);
          seeds.push_back(s);
        });
      }
    });
    cellBase += nc;
  }
  // The particle files' particles as they are, each on the rank of its point.
  for (size_t b = 0; b < sc.bodies.size(); ++b)
    if (!sc.bodies[b].file.empty()) fileSeeds(sc, grid, rank, b, seeds, overlap);
  return seeds;
}

/// Particle k's traction and penalty condition per axis (seed s, tolerance tol): the face
/// conditions its faces lie on, -1 for none; a second one on an axis is noted.
void markFaces(const Scene<3> &sc, const Seed &s, double tol, PetscInt k, ParticleView<3> &p,
               LoadConflict &conflict) {
  const Body<3> &body = sc.bodies[s.body];
  for (int a = 0; a < 3; ++a) {
    p.trac[3 * k + a] = p.dbc[3 * k + a] = -1;
    for (double nrm : {-1.0, 1.0}) {
      const double at = s.x[a] + nrm * s.l[a];
      const PetscInt t =
          faceCondition(sc.tractions, 0, body, s.body, a, nrm, at, s.x, s.l, tol, conflict);
      const PetscInt d =
          faceCondition(sc.dbcs, 1, body, s.body, a, nrm, at, s.x, s.l, tol, conflict);
      if (t >= 0 && p.trac[3 * k + a] >= 0) conflict.note(0, p.trac[3 * k + a], t);
      if (d >= 0 && p.dbc[3 * k + a] >= 0) conflict.note(1, p.dbc[3 * k + a], d);
      if (t >= 0) p.trac[3 * k + a] = t;
      if (d >= 0) p.dbc[3 * k + a] = d;
    }
  }
}

} // namespace

template <>
PetscErrorCode seedParticles<3>(const Scene<3> &sc, const Grid<3> &grid, DM sw,
                                LoadConflict &conflict) {
  PetscMPIInt rank = 0;
  PetscCallMPI(MPI_Comm_rank(PetscObjectComm(reinterpret_cast<PetscObject>(sw)), &rank));
  int overlap = 0; // the largest body index whose particle another body also holds
  const std::vector<Seed> seeds = collectSeeds(sc, grid, rank, overlap);
  conflict.noteOverlap(overlap);
  const PetscInt n = static_cast<PetscInt>(seeds.size());
  PetscCall(DMSwarmSetLocalSizes(sw, n, 4));
  ParticleView<3> p;
  PetscCall(p.get(sw));
  const double tol = 1e-9 * grid.hMin();
  for (PetscInt k = 0; k < n; ++k) {
    const Seed &s = seeds[k];
    const Body<3> &body = sc.bodies[s.body];
    const Material &mat = sc.oneMaterial ? sc.material : body.material;
    const double amp = body.sineProfile ? std::sin(body.wavenumber * (s.x[0] - body.box[0])) : 1.0;
    // A rigid rotation omega x (X - c) about the box's centre c.
    double r[3];
    for (int a = 0; a < 3; ++a)
      r[a] = s.x[a] - 0.5 * (body.box[a] + body.box[3 + a]);
    const Coords<3> &w = body.spin;
    const double spin[3] = {w[1] * r[2] - w[2] * r[1], w[2] * r[0] - w[0] * r[2],
                            w[0] * r[1] - w[1] * r[0]};
    for (int a = 0; a < 3; ++a) {
      p.x[3 * k + a] = p.X0[3 * k + a] = s.x[a];
      p.v[3 * k + a] = (s.v ? s.v[a] : body.velocity[a]) * amp + spin[a];
      p.l[3 * k + a] = p.l0[3 * k + a] = s.l[a];
    }
    p.m[k] = mat.rho * s.V;
    p.V0[k] = p.V[k] = s.V;
    for (int i = 0; i < 9; ++i) {
      p.F[9 * k + i] = i % 4 == 0 ? 1.0 : 0.0;
      if (p.B) p.B[9 * k + i] = 0.0;
    }
    for (int i = 0; i < kStress<3>; ++i)
      p.s[kStress<3> * k + i] = 0.0;
    if (p.hasCorners)
      for (int q = 0; q < 8; ++q)
        for (int a = 0; a < 3; ++a)
          p.corners[24 * k + 3 * q + a] = cpdi::cornerSign<3>(q, a) < 0 ? s.lo[a] : s.hi[a];
    if (p.eps)
      for (int a = 0; a < 3; ++a)
        p.eps[3 * k + a] = 0.0;
    p.id[k] = s.id;
    p.rank[k] = rank;
    if (!p.trac) continue;
    markFaces(sc, s, tol, k, p, conflict);
  }
  PetscCall(p.restore(sw));
  return PETSC_SUCCESS;
}

} // namespace gimp
