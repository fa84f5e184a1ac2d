#include "gimp/particles.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace gimp {

namespace {

struct FieldSpec {
  const char *name;
  PetscInt bs;
  PetscDataType type;
};

const FieldSpec kFields[] = {
    {"x", 2, PETSC_REAL},      {"X0", 2, PETSC_REAL},  {"v", 2, PETSC_REAL},
    {"m", 1, PETSC_REAL},      {"V0", 1, PETSC_REAL},  {"V", 1, PETSC_REAL},
    {"l", 2, PETSC_REAL},      {"l0", 2, PETSC_REAL},  {"F", 4, PETSC_REAL},
    {"stress", 4, PETSC_REAL}, {"eps", 2, PETSC_REAL}, {"id", 1, PETSC_INT64},
    {"trac", 2, PETSC_INT},    {"dbc", 2, PETSC_INT}};

template <typename T> PetscErrorCode getField(DM sw, const char *name, T **p) {
  PetscCall(DMSwarmGetField(sw, name, nullptr, nullptr, reinterpret_cast<void **>(p)));
  return PETSC_SUCCESS;
}

template <typename T> PetscErrorCode restoreField(DM sw, const char *name, T **p) {
  PetscCall(DMSwarmRestoreField(sw, name, nullptr, nullptr, reinterpret_cast<void **>(p)));
  return PETSC_SUCCESS;
}

} // namespace

PetscErrorCode ParticleView::get(DM sw) {
  PetscObject mark = nullptr;
  PetscCall(PetscObjectQuery(reinterpret_cast<PetscObject>(sw), "gimp_corners", &mark));
  hasCorners = mark != nullptr;
  PetscCall(DMSwarmGetLocalSize(sw, &n));
  PetscCall(getField(sw, "x", &x));
  PetscCall(getField(sw, "X0", &X0));
  PetscCall(getField(sw, "v", &v));
  PetscCall(getField(sw, "m", &m));
  PetscCall(getField(sw, "V0", &V0));
  PetscCall(getField(sw, "V", &V));
  PetscCall(getField(sw, "l", &l));
  PetscCall(getField(sw, "l0", &l0));
  PetscCall(getField(sw, "F", &F));
  PetscCall(getField(sw, "stress", &s));
  PetscCall(getField(sw, "eps", &eps));
  PetscCall(getField(sw, "id", &id));
  PetscCall(getField(sw, "trac", &trac));
  PetscCall(getField(sw, "dbc", &dbc));
  if (hasCorners) PetscCall(getField(sw, "corners", &corners));
  PetscCall(getField(sw, DMSwarmField_rank, &rank));
  return PETSC_SUCCESS;
}

PetscErrorCode ParticleView::restore(DM sw) {
  PetscCall(restoreField(sw, "x", &x));
  PetscCall(restoreField(sw, "X0", &X0));
  PetscCall(restoreField(sw, "v", &v));
  PetscCall(restoreField(sw, "m", &m));
  PetscCall(restoreField(sw, "V0", &V0));
  PetscCall(restoreField(sw, "V", &V));
  PetscCall(restoreField(sw, "l", &l));
  PetscCall(restoreField(sw, "l0", &l0));
  PetscCall(restoreField(sw, "F", &F));
  PetscCall(restoreField(sw, "stress", &s));
  PetscCall(restoreField(sw, "eps", &eps));
  PetscCall(restoreField(sw, "id", &id));
  PetscCall(restoreField(sw, "trac", &trac));
  PetscCall(restoreField(sw, "dbc", &dbc));
  if (hasCorners) PetscCall(restoreField(sw, "corners", &corners));
  PetscCall(restoreField(sw, DMSwarmField_rank, &rank));
  return PETSC_SUCCESS;
}

PetscErrorCode createSwarm(MPI_Comm comm, bool corners, DM *sw) {
  PetscCall(DMCreate(comm, sw));
  PetscCall(DMSetType(*sw, DMSWARM));
  PetscCall(PetscObjectSetName(reinterpret_cast<PetscObject>(*sw), "particles"));
  PetscCall(DMSetDimension(*sw, 2));
  PetscCall(DMSwarmSetType(*sw, DMSWARM_BASIC));
  PetscCall(DMSwarmInitializeFieldRegister(*sw));
  for (const FieldSpec &f : kFields)
    PetscCall(DMSwarmRegisterPetscDatatypeField(*sw, f.name, f.bs, f.type));
  // Corner positions (x, y of the corners (-,-), (+,-), (+,+), (-,+)) only when tracked.
  if (corners) PetscCall(DMSwarmRegisterPetscDatatypeField(*sw, "corners", 8, PETSC_REAL));
  PetscCall(DMSwarmFinalizeFieldRegister(*sw));
  if (corners) { // mark the swarm, so that ParticleView::get knows the field is there
    PetscContainer mark;
    PetscCall(PetscContainerCreate(comm, &mark));
    PetscCall(PetscObjectCompose(reinterpret_cast<PetscObject>(*sw), "gimp_corners",
                                 reinterpret_cast<PetscObject>(mark)));
    PetscCall(PetscContainerDestroy(&mark));
  }
  return PETSC_SUCCESS;
}

/// Whether the square particle (x, y, half-size l) of body b has an edge on the segment.
bool onSegment(const Scene &sc, const Segment &seg, int b, double x, double y, double l,
               double tol) {
  if (seg.body != b) return false;
  const Box &box = sc.bodies[b].box;
  const int a = seg.axis();
  const double edge = (a == 0 ? x : y) + seg.normal() * l;
  const double target = a == 0 ? (seg.side == Side::Left ? box[0] : box[2])
                               : (seg.side == Side::Bottom ? box[1] : box[3]);
  if (std::fabs(edge - target) > tol) return false;
  const double along = a == 0 ? y : x;
  return !seg.hasRange || (along >= seg.range[0] && along <= seg.range[1]);
}

PetscErrorCode seedParticles(const Scene &sc, const Grid &g, DM sw) {
  struct Seed {
    double x, y, l;
    double cx0, cx1, cy0, cy1; // corners from the sub-cell lattice: neighbours share them exactly
    PetscInt64 id;
    int body;
  };
  std::vector<Seed> seeds;
  PetscMPIInt rank = 0;
  PetscCallMPI(MPI_Comm_rank(PetscObjectComm(reinterpret_cast<PetscObject>(sw)), &rank));
  const int K = static_cast<int>(g.levels.size());
  PetscInt64 maxCells = 0;
  for (const Level &L : g.levels)
    maxCells = std::max<PetscInt64>(maxCells, static_cast<PetscInt64>(L.M) * L.N);
  // Leaf cells of every level: a body's particles take the size of the finest cell there.
  // The rank owning the level-0 cell of a leaf cell's centre seeds it.
  for (size_t b = 0; b < sc.bodies.size(); ++b) {
    const Body &body = sc.bodies[b];
    for (int q = 0; q < K; ++q) {
      const Level &L = g.levels[q];
      const double h = L.h;
      const double band = body.holeBand > 0 ? body.holeBand : h;
      const PetscInt i0 =
          std::max<PetscInt>(0, static_cast<PetscInt>(std::floor((body.box[0] - L.box[0]) / h)));
      const PetscInt j0 =
          std::max<PetscInt>(0, static_cast<PetscInt>(std::floor((body.box[1] - L.box[1]) / h)));
      const PetscInt i1 = std::min<PetscInt>(
          L.M - 1, static_cast<PetscInt>(std::ceil((body.box[2] - L.box[0]) / h)));
      const PetscInt j1 = std::min<PetscInt>(
          L.N - 1, static_cast<PetscInt>(std::ceil((body.box[3] - L.box[1]) / h)));
      for (PetscInt j = j0; j < j1; ++j)
        for (PetscInt i = i0; i < i1; ++i) {
          const double cx0 = L.box[0] + i * h, cy0 = L.box[1] + j * h;
          if (g.leafLevelAt(cx0 + 0.5 * h, cy0 + 0.5 * h) != q) continue;
          if (g.ownerOf(cx0 + 0.5 * h, cy0 + 0.5 * h) != rank) continue;
          if (cx0 + h <= body.box[0] || cx0 >= body.box[2] || cy0 + h <= body.box[1] ||
              cy0 >= body.box[3])
            continue;
          int ppc = body.ppc;
          for (const Hole &c : body.holes) {
            // Nearest and farthest points of the cell from the hole centre.
            const double nx = std::clamp(c.cx, cx0, cx0 + h), ny = std::clamp(c.cy, cy0, cy0 + h);
            const double dmin = std::hypot(nx - c.cx, ny - c.cy);
            const double fx = std::max(std::fabs(cx0 - c.cx), std::fabs(cx0 + h - c.cx));
            const double fy = std::max(std::fabs(cy0 - c.cy), std::fabs(cy0 + h - c.cy));
            if (dmin <= c.r + band && std::hypot(fx, fy) >= c.r) ppc = body.holePpc;
          }
          const int n = static_cast<int>(std::lround(std::sqrt(static_cast<double>(ppc))));
          const double d = h / n;
          const PetscInt64 cell = static_cast<PetscInt64>(j) * L.M + i;
          for (int b2 = 0; b2 < n; ++b2)
            for (int a = 0; a < n; ++a) {
              const double x = cx0 + (a + 0.5) * d, y = cy0 + (b2 + 0.5) * d;
              if (!body.inside(x, y)) continue;
              // Unique and independent of the rank count: body, level, cell, sub-cell.
              const PetscInt64 id =
                  (((static_cast<PetscInt64>(b) * K + q) * maxCells + cell) * 64 + b2) * 64 + a;
              const PetscInt64 nx = static_cast<PetscInt64>(i) * n + a,
                               ny = static_cast<PetscInt64>(j) * n + b2;
              seeds.push_back({x, y, 0.5 * d, L.box[0] + nx * d, L.box[0] + (nx + 1) * d,
                               L.box[1] + ny * d, L.box[1] + (ny + 1) * d, id,
                               static_cast<int>(b)});
            }
        }
    }
  }
  PetscCall(DMSwarmSetLocalSizes(sw, static_cast<PetscInt>(seeds.size()), 16));
  ParticleView p;
  PetscCall(p.get(sw));
  const Material &mat = sc.material;
  const double tol = 1e-9 * g.hMin();
  for (PetscInt k = 0; k < p.n; ++k) {
    const Seed &s = seeds[k];
    const Body &body = sc.bodies[s.body];
    p.x[2 * k] = p.X0[2 * k] = s.x;
    p.x[2 * k + 1] = p.X0[2 * k + 1] = s.y;
    double vx = body.velocity[0], vy = body.velocity[1];
    if (body.sineProfile) {
      const double f = std::sin(body.wavenumber * (s.x - body.box[0]));
      vx *= f;
      vy *= f;
    }
    p.v[2 * k] = vx;
    p.v[2 * k + 1] = vy;
    p.V0[k] = p.V[k] = 4.0 * s.l * s.l * mat.thickness;
    p.m[k] = mat.rho * p.V0[k];
    p.l[2 * k] = p.l[2 * k + 1] = p.l0[2 * k] = p.l0[2 * k + 1] = s.l;
    if (p.hasCorners) {
      const double c[8] = {s.cx0, s.cy0, s.cx1, s.cy0, s.cx1, s.cy1, s.cx0, s.cy1};
      std::copy(c, c + 8, &p.corners[8 * k]);
    }
    p.F[4 * k] = p.F[4 * k + 3] = 1.0;
    p.F[4 * k + 1] = p.F[4 * k + 2] = 0.0;
    for (int c = 0; c < 4; ++c)
      p.s[4 * k + c] = 0.0;
    p.eps[2 * k] = p.eps[2 * k + 1] = 0.0;
    p.id[k] = s.id;
    p.rank[k] = rank;
    p.trac[2 * k] = p.trac[2 * k + 1] = -1;
    p.dbc[2 * k] = p.dbc[2 * k + 1] = -1;
    for (size_t t = 0; t < sc.tractions.size(); ++t)
      if (onSegment(sc, sc.tractions[t], s.body, s.x, s.y, s.l, tol))
        p.trac[2 * k + sc.tractions[t].axis()] = static_cast<PetscInt>(t);
    for (size_t t = 0; t < sc.dbcs.size(); ++t)
      if (onSegment(sc, sc.dbcs[t], s.body, s.x, s.y, s.l, tol))
        p.dbc[2 * k + sc.dbcs[t].axis()] = static_cast<PetscInt>(t);
  }
  PetscCall(p.restore(sw));
  return PETSC_SUCCESS;
}

} // namespace gimp
