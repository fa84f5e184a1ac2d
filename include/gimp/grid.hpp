// The background grid: nested uniform levels (paper section 3). Level 0 covers the domain;
// level k+1 is a box inside level k, its corners on level-k grid lines, its cell size h_k / r.
// A node shared by several levels belongs to the finest; coarse nodes covered by a finer box
// are inactive. Every active node has an influence zone [Lx-, Lx+, Ly-, Ly+]: on each side the
// width of the leaf cells touching it there (the smaller one where two differ), zero outside
// the domain. A single uniform level is the case of one box.
//
// Storage. Each level is a DMDA (dof 2); the levels compose (DMComposite) into the global Vec
// that TS advances. Each rank works on a window of every level: the nodes within two level-0
// cells of the level-0 cells it owns (particles are owned by the rank owning their level-0
// cell). A VecScatter moves values between the global Vec and the window (insert forward, add
// in reverse), so P2G and G2P run on plain arrays.
#pragma once

#include "gimp/scene.hpp"

#include <petscdmcomposite.h>
#include <petscdmda.h>

#include <cstdint>
#include <vector>

namespace gimp {

struct Level {
  DM da = nullptr;  // dof 2
  DM da1 = nullptr; // dof 1 (output of scalar fields)
  double h = 0;
  Box box{};                                   // [m]
  std::int64_t u0 = 0, v0 = 0;                 // lower-left corner in finest-lattice units
  std::int64_t u1 = 0, v1 = 0;                 // upper-right corner
  std::int64_t step = 1;                       // cell size in finest-lattice units
  PetscInt M = 0, N = 0;                       // nodes in x and y
  PetscInt wi0 = 0, wi1 = 0, wj0 = 0, wj1 = 0; // this rank's window [wi0, wi1) x [wj0, wj1)
  PetscInt offset = 0;                         // first window node of this level
  PetscInt wnx() const { return wi1 - wi0; }
};

/// Nodes and weights of every particle, in compressed rows: entries start[k]..start[k+1]-1 of
/// particle k, each a window node and the 1D weights and gradients of Eq. 15 in x and y. The
/// arrays keep their capacity between steps: only the first start[n] entries are valid.
struct Stencils {
  std::vector<PetscInt> start;
  std::vector<PetscInt> node;
  std::vector<double> wx, wy, gx, gy;
};

class Grid {
public:
  Grid() = default;
  Grid(const Grid &) = delete;
  Grid &operator=(const Grid &) = delete;
  ~Grid();

  /// Build the levels from the scene (validated there), the composite DM, this rank's window
  /// and its scatter (collective).
  PetscErrorCode create(MPI_Comm comm, const Scene &sc);

  /// Geometry only (no PETSc objects): enough for zones, activity and dumps. Throws InputError
  /// for a layout that is not properly nested.
  void setGeometry(const Scene &sc);

  std::vector<Level> levels;
  DM dm = nullptr;                 // DMComposite of the level DMDAs
  double x0 = 0, y0 = 0, unit = 0; // domain origin, finest-lattice unit [m]
  double hMin() const { return levels.back().h; }
  double h0() const { return levels.front().h; }

  // Window node data (all levels concatenated).
  PetscInt nWindow = 0;
  std::vector<std::uint8_t> active, regular;
  std::vector<double> X, Y;
  std::vector<double> zone; // 4 per node: Lx-, Lx+, Ly-, Ly+

  /// Vectors on the window (sequential, dof 2) and moves between them and a global Vec.
  PetscErrorCode createWindowVec(Vec *v) const;
  PetscErrorCode toWindow(Vec global, Vec window) const;      // insert
  PetscErrorCode addFromWindow(Vec window, Vec global) const; // add (caller zeroes global)

  /// Rank owning the level-0 cell containing (x, y).
  PetscMPIInt ownerOf(double x, double y) const;
  /// The region of rank r's level-0 cells [x0, y0, x1, y1] (unbounded at the domain edges).
  void ownedBox(PetscMPIInt r, double box[4]) const;

  /// Active nodes, zones and the stencils of n particles (positions x, half-sizes l).
  void buildStencils(PetscInt n, const double *x, const double *l, Stencils &s) const;

  // Pure geometry, in level k's node indices.
  bool nodeActive(int k, std::int64_t i, std::int64_t j) const;
  void zonesOf(int k, std::int64_t i, std::int64_t j, double z[4]) const;
  /// Level whose leaf cell contains the point at doubled lattice coordinates (a, b), which
  /// must not lie on a grid line; -1 outside the domain.
  int leafLevelAt2(std::int64_t a, std::int64_t b) const;
  /// Level of the leaf cell containing (x, y) [m].
  int leafLevelAt(double x, double y) const;
  std::int64_t activeNodes(int k) const;

  /// Active nodes as CSV level,x,y,Lxm,Lxp,Lym,Lyp (rank 0 writes).
  PetscErrorCode dump(MPI_Comm comm, const std::string &file) const;

  /// Index of the level-0 grid line at coordinate c on axis (0: x, 1: y), or -1.
  PetscInt lineIndex(int axis, double c) const;

private:
  static constexpr std::uint8_t kActive = 1, kRegular = 2;
  std::vector<std::uint8_t> flags_;   // active and regular in one byte per window node
  std::vector<std::uint8_t> block3_;  // the 3 x 3 block of one level from this node is regular
  std::vector<PetscInt> ownX_, ownY_; // level-0 node ownership: first node of each rank column
  VecScatter scatter_ = nullptr;
  Vec windowTemplate_ = nullptr;
};

} // namespace gimp
