// Throughput of the explicit step's particle kernels in 2D and 3D, on one core: the work a step
// does per particle (stencils, P2G, internal force, the nodal velocity and acceleration, G2P,
// velocity gradient, stress update and the particles' move), without the solver's scene,
// output and TS around it. The 3D solver does not exist yet; this measures what its step
// would cost per particle with the kernels it will use, and the 2D line is the same loop with
// the 2D kernels, to set it against the 2D solver's own figures (docs/performance.md).
//
// Usage: build/bench/kernels3d [-cells N] [-ppc n] [-steps S] [-transfer flip|apic]
//          [-levels 1|3] [-dim 2|3 (default both)]
// A block of N^D level-0 cells filled with n^D particles per cell (with -levels 3, a fine box of
// ratio 2 over the middle half of each axis and a box of ratio 2 inside it over the middle
// quarter, the particles filling the leaf cells). Prints particle-steps per second and the
// bytes of the per-particle arrays the loop holds.
#include "gimp/grid/grid.hpp"
#include "gimp/physics/material.hpp"
#include "gimp/transfer/affine.hpp"
#include "gimp/transfer/internal_force.hpp"
#include "gimp/transfer/transfer.hpp"

#include <petscsys.h>
#include <petsctime.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

namespace {

struct Options {
  PetscInt cells = 16, ppc = 2, steps = 20, levels = 1, dim = 0; // dim 0: both
  bool apic = false;
};

template <int D> struct Bench {
  gimp::Grid<D> grid;
  std::vector<double> x, l, v, m, V, s, B, L, xs, mom, mass, f, vg, ag;
  gimp::Stencils<D> st;

  PetscErrorCode setup(const Options &o) {
    const double h0 = 1.0 / o.cells;
    std::vector<gimp::LevelBox<D>> boxes(1);
    for (int a = 0; a < D; ++a) {
      boxes[0].box[a] = 0.0;
      boxes[0].box[D + a] = 1.0;
    }
    if (o.levels == 3) {
      gimp::LevelBox<D> b1, b2;
      for (int a = 0; a < D; ++a) {
        b1.box[a] = h0 * (o.cells / 4);
        b1.box[D + a] = h0 * (o.cells - o.cells / 4);
        b2.box[a] = h0 * (3 * o.cells / 8);
        b2.box[D + a] = h0 * (o.cells - 3 * o.cells / 8);
      }
      b1.ratio = b2.ratio = 2;
      boxes.push_back(b1);
      boxes.push_back(b2);
    }
    PetscCall(grid.create(PETSC_COMM_SELF, h0, boxes));
    // Particles filling the leaf cells inside [h0, 1 - h0]^D (a margin of one level-0 cell).
    for (int k = 0; k < static_cast<int>(grid.levels.size()); ++k) {
      const gimp::Level<D> &Lv = grid.levels[k];
      std::array<PetscInt, D> cells;
      for (int a = 0; a < D; ++a)
        cells[a] = Lv.n[a] - 1;
      gimp::forEachIndex<D>(cells, [&](const gimp::LatticeIndex<D> &c) {
        double lo[D], centre[D];
        bool in = true;
        for (int a = 0; a < D; ++a) {
          lo[a] = Lv.box[a] + c[a] * Lv.h;
          centre[a] = lo[a] + 0.5 * Lv.h;
          in = in && centre[a] > h0 && centre[a] < 1.0 - h0;
        }
        if (!in || grid.leafLevelAt(centre) != k) return;
        const double d = Lv.h / o.ppc;
        std::array<PetscInt, D> sub;
        sub.fill(o.ppc);
        gimp::forEachIndex<D>(sub, [&](const gimp::LatticeIndex<D> &q) {
          double vol = 1.0;
          for (int a = 0; a < D; ++a) {
            x.push_back(lo[a] + (q[a] + 0.5) * d);
            l.push_back(0.5 * d);
            v.push_back(1e-3 * (a + 1));
            vol *= d;
          }
          V.push_back(vol);
          m.push_back(1000.0 * vol);
        });
      });
    }
    const size_t n = m.size();
    s.assign(gimp::kStress<D> * n, 0.0);
    B.assign(D * D * n, 0.0);
    L.assign(D * D * n, 0.0);
    const size_t slots = static_cast<size_t>(grid.nSlots);
    xs.resize(D * slots);
    for (size_t q = 0; q < slots; ++q)
      for (int a = 0; a < D; ++a)
        xs[D * q + a] = grid.coordinates(a)[grid.slotNode[q]];
    mom.resize(D * slots);
    mass.resize(D * slots);
    f.resize(D * slots);
    vg.resize(D * slots);
    ag.resize(D * slots);
    return PETSC_SUCCESS;
  }

  /// One step of the kernels; false if a stencil could not be built.
  bool step(const Options &o, const gimp::Material &mat, double dt) {
    const PetscInt n = static_cast<PetscInt>(m.size());
    if (!grid.buildStencils(n, x.data(), l.data(), st, true)) return false;
    std::fill(mom.begin(), mom.end(), 0.0);
    std::fill(mass.begin(), mass.end(), 0.0);
    std::fill(f.begin(), f.end(), 0.0);
    if (o.apic)
      gimp::transfer::particlesToGridAffineB<D>(st, n, m.data(), v.data(), B.data(), x.data(),
                                                xs.data(), mom.data(), mass.data());
    else
      gimp::transfer::particlesToGrid<D>(st, n, m.data(), v.data(), mom.data(), mass.data());
    gimp::transfer::internalForce<D>(st, n, V.data(), s.data(), f.data());
    const size_t slots = mass.size() / D;
    for (size_t q = 0; q < slots; ++q) {
      const double mq = mass[D * q];
      for (int a = 0; a < D; ++a) {
        const double acc = mq > 0 ? f[D * q + a] / mq : 0.0;
        ag[D * q + a] = acc;
        vg[D * q + a] = mq > 0 ? mom[D * q + a] / mq + dt * acc : 0.0;
      }
    }
    if (o.apic)
      gimp::transfer::gridToParticlesAffine<D>(st, n, vg.data(), x.data(), xs.data(), dt, v.data(),
                                               B.data(), x.data());
    else
      gimp::transfer::gridToParticles<D>(st, n, vg.data(), ag.data(), dt, 1.0, v.data(), x.data());
    gimp::transfer::velocityGradient<D>(st, n, vg.data(), L.data());
    for (PetscInt k = 0; k < n; ++k) {
      const gimp::Tensor<D> Lk = gimp::tensorAt<D>(L.data(), k);
      gimp::Tensor<D> sk = gimp::stressAt<D>(s.data(), k);
      if constexpr (D == 2) {
        double szz = 0;
        gimp::material::jaumannUpdate(mat, Lk, dt, sk, szz);
      } else {
        gimp::material::jaumannUpdate(mat, Lk, dt, sk);
      }
      gimp::setStress<D>(s.data(), k, sk);
    }
    return true;
  }

  PetscErrorCode run(const Options &o) {
    PetscCall(setup(o));
    gimp::Material mat;
    mat.E = 2e9;
    mat.nu = 0.3;
    mat.rho = 1000.0;
    mat.mu = mat.E / (2 * (1 + mat.nu));
    mat.lambda = mat.E * mat.nu / ((1 + mat.nu) * (1 - 2 * mat.nu));
    mat.lambdaStar = mat.lambda;
    const double dt = 0.1 * grid.hMin() / std::sqrt((mat.lambda + 2 * mat.mu) / mat.rho);
    PetscCheck(step(o, mat, dt), PETSC_COMM_SELF, PETSC_ERR_PLIB, "stencils failed");
    PetscLogDouble t0, t1;
    PetscCall(PetscTime(&t0));
    for (PetscInt k = 0; k < o.steps; ++k)
      PetscCheck(step(o, mat, dt), PETSC_COMM_SELF, PETSC_ERR_PLIB, "stencils failed");
    PetscCall(PetscTime(&t1));
    const double n = static_cast<double>(m.size());
    // The loop's per-particle arrays: x, l, v, m, V, s, B (APIC), L and the stencils.
    const double fields = (3.0 * D + 2.0 + D * D * (o.apic ? 3.0 : 2.0)) * sizeof(double);
    const double stencil =
        (static_cast<double>(st.node.capacity()) * (sizeof(PetscInt) + 2.0 * D * sizeof(double)) +
         static_cast<double>(st.blocks.capacity()) * sizeof(gimp::Block<D>) +
         static_cast<double>(st.blockOf.capacity() + st.start.capacity()) * sizeof(PetscInt)) /
        n;
    PetscCall(
        PetscPrintf(PETSC_COMM_SELF,
                    "%dD %-4s levels %" PetscInt_FMT ": %9.0f particles, %6.2f M particle-"
                    "steps/s, %5.0f B/particle (fields %3.0f, stencils %3.0f; %.0f%% blocks)\n",
                    D, o.apic ? "apic" : "flip", o.levels, n, n * o.steps / (t1 - t0) / 1e6,
                    fields + stencil, fields, stencil, 100.0 * st.nBlocks / n));
    return PETSC_SUCCESS;
  }
};

} // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  Options o;
  char transfer[16] = "flip";
  PetscCall(PetscOptionsGetInt(nullptr, nullptr, "-cells", &o.cells, nullptr));
  PetscCall(PetscOptionsGetInt(nullptr, nullptr, "-ppc", &o.ppc, nullptr));
  PetscCall(PetscOptionsGetInt(nullptr, nullptr, "-steps", &o.steps, nullptr));
  PetscCall(PetscOptionsGetInt(nullptr, nullptr, "-levels", &o.levels, nullptr));
  PetscCall(PetscOptionsGetInt(nullptr, nullptr, "-dim", &o.dim, nullptr));
  PetscCall(
      PetscOptionsGetString(nullptr, nullptr, "-transfer", transfer, sizeof(transfer), nullptr));
  o.apic = std::string(transfer) == "apic";
  PetscCheck(o.cells >= 8 && o.ppc >= 1 && o.steps >= 1 && (o.levels == 1 || o.levels == 3),
             PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE,
             "-cells >= 8, -ppc >= 1, -steps >= 1, -levels 1 or 3");
  {
    Options o2 = o;
    o2.cells = o.cells * 8; // the 2D block with as many particles as the 3D one at ppc 2, 16^3
    Bench<2> b2;
    if (o.dim != 3) PetscCall(b2.run(o2));
    Bench<3> b3;
    if (o.dim != 2) PetscCall(b3.run(o));
  }
  PetscCall(PetscFinalize());
  return 0;
}
