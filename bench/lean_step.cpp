// A lean reference of gimp's default explicit step on the benchmark block, written for that
// scene alone: one uniform level, every particle a 3 x 3 block, GIMP weights, APIC transfers
// with MUSL (the re-projected grid velocity drives the stress update), linear elasticity with
// the Jaumann rate in plane strain, stretch tracking of the particle domains. No scene input,
// no levels, no rows, no TS, no output between steps, no checks beyond the domain's size.
//
// Two uses (docs/performance.md, *A lean reference step*):
//   - speed: what a plain single-purpose implementation of the same step costs per particle,
//     against gimp's general one on `bench/block.opts` (same particles, same answer);
//   - results: an independent implementation of the whole step. tests/check_lean_step.py
//     compares every particle's state after a few steps with gimp's (-out writes it).
//
// Usage: build/bench/lean_step [-cells N (128)] [-steps S (1000)] [-out FILE]
// The block is [0, 1]^2 with N x N cells of h = 1/N and 2 x 2 particles per cell,
// E = 1 GPa, nu = 0.3, rho = 1000 kg/m^3, v_x = v_y = sin(2 pi x) m/s, dt = 0.3 h / c_p:
// the scene of bench/block.opts. -out writes, per particle in seeding order, the text columns
// X0_x X0_y x_x x_y v_x v_y B_xx B_xy B_yx B_yy s_xx s_xy s_yy s_zz V l_x l_y.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

constexpr double kPi = 3.14159265358979323846;

/// A particle's 1D factors on its 3 x 3 block of nodes, and its APIC D_p^-1 (diagonal on a
/// uniform grid: the weights reproduce linear functions, so the cross moments vanish).
struct Block {
  double wx[3], gx[3], wy[3], gy[3];
  double dix, diy; // 1 / D_xx, 1 / D_yy
  long n0;         // the block's first node
  long i0, j0;     // its node indices
};

/// GIMP weights and slopes of the 3 nodes i0 .. i0+2 for a particle whose ends, in cells from
/// node i0, are xi -+ lam (left end in [0, 1), lam <= 1/2): the integral of each node's tent
/// over the particle, divided by its length.
void weights3(double xi, double lam, double ih, double *w, double *g) {
  const double a = xi - lam, b = xi + lam;
  const double bb = std::fmin(1.0, b), c = std::fmax(0.0, b - 1.0);
  const double ua = 1.0 - a, ub = 1.0 - bb;
  const double i2l = 0.5 / lam, i2lh = i2l * ih;
  w[0] = 0.5 * (ua - ub) * (ua + ub) * i2l;
  w[1] = (0.5 * (bb - a) * (bb + a) + c - 0.5 * c * c) * i2l;
  w[2] = 0.5 * c * c * i2l;
  g[0] = (ub - ua) * i2lh;
  g[1] = (1.0 - std::fabs(b - 1.0) - a) * i2lh;
  g[2] = c * i2lh;
}

struct Lean {
  int N;
  double h, ih, dt, lambda, mu;
  long nodesPerRow, nodes, np;
  // particles
  std::vector<double> X0, x, v, B, F, s, szz, l, l0, m, V, V0;
  std::vector<Block> block;
  // nodes, with one node of padding around the block
  std::vector<double> mass, mom, force, vel, mom2;

  explicit Lean(int cells) : N(cells) {
    const double E = 1e9, nu = 0.3, rho = 1000.0;
    h = 1.0 / N;
    ih = N;
    lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
    mu = E / (2 * (1 + nu));
    dt = 0.3 * h / std::sqrt((lambda + 2 * mu) / rho);
    nodesPerRow = N + 3;
    nodes = nodesPerRow * nodesPerRow;
    np = 4L * N * N;
    for (auto *f : {&X0, &x, &v, &l, &l0})
      f->assign(2 * np, 0.0);
    for (auto *f : {&B, &F, &s})
      f->assign(4 * np, 0.0);
    for (auto *f : {&szz, &m, &V, &V0})
      f->assign(np, 0.0);
    block.resize(np);
    for (auto *f : {&mass})
      f->assign(nodes, 0.0);
    for (auto *f : {&mom, &force, &vel, &mom2})
      f->assign(2 * nodes, 0.0);
    long k = 0;
    for (int cy = 0; cy < N; ++cy)
      for (int cx = 0; cx < N; ++cx)
        for (int qy = 0; qy < 2; ++qy)
          for (int qx = 0; qx < 2; ++qx, ++k) {
            x[2 * k] = X0[2 * k] = (cx + 0.25 + 0.5 * qx) * h;
            x[2 * k + 1] = X0[2 * k + 1] = (cy + 0.25 + 0.5 * qy) * h;
            v[2 * k] = v[2 * k + 1] = std::sin(2 * kPi * x[2 * k]);
            for (int a = 0; a < 2; ++a)
              l[2 * k + a] = l0[2 * k + a] = 0.25 * h;
            V[k] = V0[k] = 0.25 * h * h;
            m[k] = rho * V[k];
            F[4 * k] = F[4 * k + 3] = 1.0;
          }
  }

  /// Offsets of the block's first node from the particle, in metres (padding: node i sits at
  /// (i - 1) h).
  void offsets(const Block &b, long p, double &dx0, double &dy0) const {
    dx0 = (b.i0 - 1) * h - x[2 * p];
    dy0 = (b.j0 - 1) * h - x[2 * p + 1];
  }

  /// Weights, D_p^-1, then the mass, the affine momentum and the internal force to the nodes.
  void particlesToGrid() {
    std::memset(mass.data(), 0, sizeof(double) * nodes);
    std::memset(mom.data(), 0, sizeof(double) * 2 * nodes);
    std::memset(force.data(), 0, sizeof(double) * 2 * nodes);
    for (long p = 0; p < np; ++p) {
      Block &b = block[p];
      const double lx = l[2 * p] * ih, ly = l[2 * p + 1] * ih;
      const double xc = x[2 * p] * ih + 1, yc = x[2 * p + 1] * ih + 1;
      b.i0 = static_cast<long>(std::floor(xc - lx));
      b.j0 = static_cast<long>(std::floor(yc - ly));
      b.n0 = b.j0 * nodesPerRow + b.i0;
      weights3(xc - b.i0, lx, ih, b.wx, b.gx);
      weights3(yc - b.j0, ly, ih, b.wy, b.gy);
      double dx0, dy0;
      offsets(b, p, dx0, dy0);
      double dxx = 0, dyy = 0;
      for (int i = 0; i < 3; ++i) {
        const double dx = dx0 + i * h, dy = dy0 + i * h;
        dxx += b.wx[i] * dx * dx;
        dyy += b.wy[i] * dy * dy;
      }
      b.dix = 1.0 / dxx;
      b.diy = 1.0 / dyy;
      const double mp = m[p], *Bp = &B[4 * p], *sp = &s[4 * p];
      const double c00 = Bp[0] * b.dix, c01 = Bp[1] * b.diy, c10 = Bp[2] * b.dix,
                   c11 = Bp[3] * b.diy;
      const double s00 = V[p] * sp[0], s01 = V[p] * sp[1], s11 = V[p] * sp[3];
      for (int j = 0; j < 3; ++j) {
        const double dy = dy0 + j * h;
        const double ax = mp * (v[2 * p] + c01 * dy), ay = mp * (v[2 * p + 1] + c11 * dy);
        const long r = b.n0 + j * nodesPerRow;
        for (int i = 0; i < 3; ++i) {
          const double dx = dx0 + i * h, w = b.wx[i] * b.wy[j];
          const double gxw = b.gx[i] * b.wy[j], gyw = b.wx[i] * b.gy[j];
          mass[r + i] += w * mp;
          mom[2 * (r + i)] += w * (ax + mp * c00 * dx);
          mom[2 * (r + i) + 1] += w * (ay + mp * c10 * dx);
          force[2 * (r + i)] -= s00 * gxw + s01 * gyw;
          force[2 * (r + i) + 1] -= s01 * gxw + s11 * gyw;
        }
      }
    }
  }

  /// The updated nodal velocity (p + dt f) / m.
  void gridUpdate() {
    for (long n = 0; n < nodes; ++n) {
      const double im = mass[n] > 0 ? 1.0 / mass[n] : 0.0;
      for (int a = 0; a < 2; ++a)
        vel[2 * n + a] = (mom[2 * n + a] + dt * force[2 * n + a]) * im;
    }
  }

  /// APIC G2P (v_p, B_p), the move, and the re-projection of the particle's new affine momentum.
  void gridToParticles() {
    std::memset(mom2.data(), 0, sizeof(double) * 2 * nodes);
    for (long p = 0; p < np; ++p) {
      const Block &b = block[p];
      double dx0, dy0;
      offsets(b, p, dx0, dy0);
      double vx = 0, vy = 0, b00 = 0, b01 = 0, b10 = 0, b11 = 0;
      for (int j = 0; j < 3; ++j) {
        const double dy = dy0 + j * h;
        const long r = b.n0 + j * nodesPerRow;
        double sx = 0, sy = 0, tx = 0, ty = 0;
        for (int i = 0; i < 3; ++i) {
          const double dx = dx0 + i * h, w = b.wx[i];
          const double ux = vel[2 * (r + i)], uy = vel[2 * (r + i) + 1];
          sx += w * ux;
          sy += w * uy;
          tx += w * ux * dx;
          ty += w * uy * dx;
        }
        vx += b.wy[j] * sx;
        vy += b.wy[j] * sy;
        b00 += b.wy[j] * tx;
        b10 += b.wy[j] * ty;
        b01 += b.wy[j] * sx * dy;
        b11 += b.wy[j] * sy * dy;
      }
      v[2 * p] = vx;
      v[2 * p + 1] = vy;
      double *Bp = &B[4 * p];
      Bp[0] = b00;
      Bp[1] = b01;
      Bp[2] = b10;
      Bp[3] = b11;
      const double mp = m[p];
      const double c00 = b00 * b.dix, c01 = b01 * b.diy, c10 = b10 * b.dix, c11 = b11 * b.diy;
      for (int j = 0; j < 3; ++j) {
        const double dy = dy0 + j * h;
        const double ax = mp * (vx + c01 * dy), ay = mp * (vy + c11 * dy);
        const long r = b.n0 + j * nodesPerRow;
        for (int i = 0; i < 3; ++i) {
          const double dx = dx0 + i * h, w = b.wx[i] * b.wy[j];
          mom2[2 * (r + i)] += w * (ax + mp * c00 * dx);
          mom2[2 * (r + i) + 1] += w * (ay + mp * c10 * dx);
        }
      }
      x[2 * p] += dt * vx;
      x[2 * p + 1] += dt * vy;
    }
    for (long n = 0; n < nodes; ++n) {
      const double im = mass[n] > 0 ? 1.0 / mass[n] : 0.0;
      for (int a = 0; a < 2; ++a)
        vel[2 * n + a] = mom2[2 * n + a] * im;
    }
  }

  /// L_p from the re-projected velocity, F += dt L F, the volume, the Jaumann stress update and
  /// the stretched domain. Returns the first particle whose domain became invalid, or -1.
  long stress() {
    for (long p = 0; p < np; ++p) {
      const Block &b = block[p];
      double L00 = 0, L01 = 0, L10 = 0, L11 = 0;
      for (int j = 0; j < 3; ++j) {
        const long r = b.n0 + j * nodesPerRow;
        double sx = 0, sy = 0, tx = 0, ty = 0;
        for (int i = 0; i < 3; ++i) {
          const double ux = vel[2 * (r + i)], uy = vel[2 * (r + i) + 1];
          sx += b.gx[i] * ux;
          sy += b.gx[i] * uy;
          tx += b.wx[i] * ux;
          ty += b.wx[i] * uy;
        }
        L00 += b.wy[j] * sx;
        L10 += b.wy[j] * sy;
        L01 += b.gy[j] * tx;
        L11 += b.gy[j] * ty;
      }
      double *Fp = &F[4 * p];
      const double f00 = Fp[0] + dt * (L00 * Fp[0] + L01 * Fp[2]);
      const double f01 = Fp[1] + dt * (L00 * Fp[1] + L01 * Fp[3]);
      const double f10 = Fp[2] + dt * (L10 * Fp[0] + L11 * Fp[2]);
      const double f11 = Fp[3] + dt * (L10 * Fp[1] + L11 * Fp[3]);
      Fp[0] = f00;
      Fp[1] = f01;
      Fp[2] = f10;
      Fp[3] = f11;
      const double J = f00 * f11 - f01 * f10;
      V[p] = V0[p] * J;
      const double d01 = 0.5 * (L01 + L10), w01 = 0.5 * (L01 - L10), tr = L00 + L11;
      double *sp = &s[4 * p];
      const double s00 = sp[0], s01 = sp[1], s11 = sp[3];
      sp[0] = s00 + dt * (lambda * tr + 2 * mu * L00 + 2 * w01 * s01);
      sp[3] = s11 + dt * (lambda * tr + 2 * mu * L11 - 2 * w01 * s01);
      sp[1] = sp[2] = s01 + dt * (2 * mu * d01 + w01 * (s11 - s00));
      szz[p] += dt * lambda * tr;
      l[2 * p] = l0[2 * p] * std::sqrt(f00 * f00 + f10 * f10);
      l[2 * p + 1] = l0[2 * p + 1] * std::sqrt(f01 * f01 + f11 * f11);
      if (!(J > 0 && l[2 * p] <= 0.5 * h && l[2 * p + 1] <= 0.5 * h)) return p;
    }
    return -1;
  }
};

} // namespace

int main(int argc, char **argv) {
  int cells = 128, steps = 1000;
  std::string out;
  for (int a = 1; a < argc; ++a) {
    const std::string key = argv[a];
    if (a + 1 >= argc) {
      std::fprintf(stderr, "lean_step: option %s needs a value\n", key.c_str());
      return 2;
    }
    const char *val = argv[++a];
    char *end = nullptr;
    if (key == "-out") {
      out = val;
      continue;
    }
    const long n = std::strtol(val, &end, 10);
    if (*end != '\0' || (key == "-cells" ? n < 2 || n > 4096 : n < 0 || n > 100000000)) {
      std::fprintf(stderr, "lean_step: %s %s: must be an integer in %s\n", key.c_str(), val,
                   key == "-cells" ? "[2, 4096]" : "[0, 1e8]");
      return 2;
    }
    if (key == "-cells")
      cells = static_cast<int>(n);
    else if (key == "-steps")
      steps = static_cast<int>(n);
    else {
      std::fprintf(stderr, "lean_step: unknown option %s (valid: -cells, -steps, -out)\n",
                   key.c_str());
      return 2;
    }
  }
  Lean lean(cells);
  const auto t0 = std::chrono::steady_clock::now();
  for (int step = 0; step < steps; ++step) {
    lean.particlesToGrid();
    lean.gridUpdate();
    lean.gridToParticles();
    const long bad = lean.stress();
    if (bad >= 0) {
      std::fprintf(stderr, "lean_step: particle %ld left the 3 x 3 block at step %d\n", bad,
                   step + 1);
      return 1;
    }
  }
  const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  double kinetic = 0;
  for (long p = 0; p < lean.np; ++p)
    kinetic +=
        0.5 * lean.m[p] * (lean.v[2 * p] * lean.v[2 * p] + lean.v[2 * p + 1] * lean.v[2 * p + 1]);
  const size_t perParticle = sizeof(double) * (2 * 5 + 4 * 3 + 4) + sizeof(Block);
  std::printf("lean_step: %ld particles, %d steps, %.3f s: %.2f M particle-steps/s, "
              "%zu B/particle held, kinetic energy %.12e J\n",
              lean.np, steps, sec,
              sec > 0 ? lean.np * static_cast<double>(steps) / sec * 1e-6 : 0.0, perParticle,
              kinetic);
  if (!out.empty()) {
    FILE *f = std::fopen(out.c_str(), "w");
    if (!f) {
      std::fprintf(stderr, "lean_step: -out %s: cannot open for writing\n", out.c_str());
      return 2;
    }
    for (long p = 0; p < lean.np; ++p) {
      const double row[] = {lean.X0[2 * p],    lean.X0[2 * p + 1], lean.x[2 * p], lean.x[2 * p + 1],
                            lean.v[2 * p],     lean.v[2 * p + 1],  lean.B[4 * p], lean.B[4 * p + 1],
                            lean.B[4 * p + 2], lean.B[4 * p + 3],  lean.s[4 * p], lean.s[4 * p + 1],
                            lean.s[4 * p + 3], lean.szz[p],        lean.V[p],     lean.l[2 * p],
                            lean.l[2 * p + 1]};
      for (double r : row)
        std::fprintf(f, "%.17g ", r);
      std::fprintf(f, "\n");
    }
    std::fclose(f);
  }
  return 0;
}
