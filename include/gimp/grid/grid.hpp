// The composite grid in PETSc: one DMDA per level (dof = dimension), composed (DMComposite) into
// the global Vec that TS advances, and this rank's window of every level.
//
// Each rank works on a window: the nodes within two level-0 cells of the level-0 cells it owns
// (particles are owned by the rank owning their level-0 cell). A VecScatter moves values between
// the global Vec and the window (insert forward, add in reverse), so P2G and G2P run on plain
// arrays and finer levels need no decomposition matching level 0.
#pragma once

#include "gimp/grid/lattice.hpp"
#include "gimp/grid/stencils.hpp"

#include <petscdmcomposite.h>
#include <petscdmda.h>

#include <cstdint>
#include <utility>
#include <vector>

namespace gimp {

class Grid : public Lattice {
public:
  /// A node whose support (widened by a particle's reach) a crack cuts.
  struct CrackedNode {
    int k;
    PetscInt i, j;
    PetscMPIInt owner; // the rank owning the node's level-0 cell
    PetscInt ownerPos; // its index among the cracked nodes of that owner
  };

  Grid() = default;
  Grid(const Grid &) = delete;
  Grid &operator=(const Grid &) = delete;
  ~Grid();

  /// Build the levels from the scene, the composite DM, this rank's window and its scatter
  /// (collective).
  PetscErrorCode create(MPI_Comm comm, const Scene &sc);

  DM dm = nullptr;         // DMComposite of the level DMDAs (and crackDm, with cracks)
  DM crackDm = nullptr;    // DMShell of the cracked nodes' second fields (dof 2), or null
  std::vector<DM> da, da1; // per level: the DMDA (dof 2) and its dof-1 twin (scalar output)

  // Window node data (all levels concatenated).
  PetscInt nWindow = 0;
  // Slots of the window arrays (D values each): the nWindow nodes, then one second velocity
  // field per cracked window node (docs/architecture.md). slotNode[s] is the window node of slot
  // s; crackSlot[n] the second slot of window node n, or -1.
  PetscInt nSlots = 0;
  std::vector<PetscInt> slotNode, crackSlot;
  std::vector<std::uint8_t> active, regular;
  std::vector<double> X, Y;
  std::vector<double> zone; // 4 per node: Lx-, Lx+, Ly-, Ly+

  /// Vectors on the window (sequential, dof 2) and moves between them and a global Vec.
  PetscErrorCode createWindowVec(Vec *v) const;
  PetscErrorCode toWindow(Vec global, Vec window) const; // insert
  /// Window values into the global Vec, combined by `mode`: ADD_VALUES sums every rank's window
  /// (the caller zeroes global first), INSERT_VALUES where every rank holding a slot has the
  /// same value, MAX_VALUES the largest (the caller sets global to -inf first).
  PetscErrorCode fromWindow(Vec window, Vec global, InsertMode mode) const;
  PetscErrorCode addFromWindow(Vec window, Vec global) const {
    return fromWindow(window, global, ADD_VALUES);
  }
  /// Every cracked node, in the order of the composite's crack part (see crack_fields.cpp).
  const std::vector<CrackedNode> &crackedNodes() const { return cracked_; }

  /// Rank owning the level-0 cell containing (x, y).
  PetscMPIInt ownerOf(double x, double y) const;
  /// The region of rank r's level-0 cells [x0, y0, x1, y1] (unbounded at the domain edges).
  void ownedBox(PetscMPIInt r, double box[4]) const;

  /// Stencils of n particles (positions x, half-sizes l; D values each). Returns false, with s
  /// unchanged past the particles done, when a particle is larger than a level-0 cell (the
  /// caller reports it collectively). With `compact` a particle inside one level's regular
  /// block keeps a block instead of rows (grid/stencils.hpp).
  bool buildStencils(PetscInt n, const double *x, const double *l, Stencils<kDim> &s,
                     bool compact = false) const;

  /// CPDI stencils (Sadeghirad et al. 2011, 2013) of n particles whose domains are the
  /// quadrilaterals of their corners (8 values each, counter-clockwise from (-, -)): general
  /// entries, S_ip = (1/A) sum_c w_c N_i(x_c) and grad S_ip = (1/A) sum_c N_i(x_c) G_c with w_c
  /// the integral of the bilinear map's corner function over the quad, G_c that of its gradient,
  /// A the quad's area, N_i the composite grid's point shape functions. Returns null, or why it
  /// could not (a corner outside the grid or the rank window, a collapsed or inverted domain),
  /// with s unchanged past the particles done.
  const char *buildCpdiStencils(PetscInt n, const double *corners, Stencils<kDim> &s) const;
  /// The point shape functions of the active nodes at (x, y) (the tent functions of Eq. 14, with
  /// the zones of transition and edge nodes): appends (slot, N) with N > 0 to `out`; returns
  /// their sum (1 inside the grid and the window).
  double pointShapes(double x, double y, std::vector<std::pair<PetscInt, double>> &out) const;
  /// Stencils of n points: general entries with the point shape functions as weights (their
  /// gradients are left zero). False when a point lies outside the grid or the window.
  bool buildPointStencils(PetscInt n, const double *x, Stencils<kDim> &s) const;

private:
  /// Level-0 ownership and this rank's window of every level.
  PetscErrorCode setWindow();
  /// Every cracked node of the grid, in an order every rank agrees on (collective-free).
  std::vector<CrackedNode> findCrackedNodes(const Scene &sc) const;
  /// The DMShell of the second fields, its window slots and their composite indices.
  PetscErrorCode addCrackFields(MPI_Comm comm, const Scene &sc);
  /// Positions, activity, zones and regularity of the window's nodes.
  void fillWindowNodes();
  /// The scatter between the composite global Vec and the window.
  PetscErrorCode createScatter(MPI_Comm comm);

  /// The candidate nodes of one level for one particle: [i0, i1] x [j0, j1] of the window,
  /// whether the particle's centre is inside the level's box, and whether they form a regular
  /// 3 x 3 block with closed-form weights.
  struct Reach {
    PetscInt i0 = 0, i1 = -1, j0 = 0, j1 = -1;
    bool inside = false, block3 = false;
  };
  bool levelReach(int q, double xp, double yp, double lx, double ly, Reach &r) const;
  void appendBlock3(const Level &L, const Reach &r, double xp, double yp, double lx, double ly,
                    Stencils<kDim> &s, size_t &m) const;
  void appendNodes(const Level &L, const Reach &r, double xp, double yp, double lx, double ly,
                   double *scratch, PetscInt maxRange, Stencils<kDim> &s, size_t &m) const;

  static constexpr std::uint8_t kActive = 1, kRegular = 2;
  std::vector<std::uint8_t> flags_;     // active and regular in one byte per window node
  std::vector<std::uint8_t> block3_;    // the 3 x 3 block of one level from this node is regular
  std::vector<PetscInt> ownX_, ownY_;   // level-0 node ownership: first node of each rank column
  std::vector<CrackedNode> cracked_;    // every cracked node (empty without cracks)
  std::vector<PetscInt> crackedOfSlot_; // index into cracked_ of each second-field slot
  std::vector<PetscInt> crackCount_;    // cracked nodes owned by each rank
  VecScatter scatter_ = nullptr;
  Vec windowTemplate_ = nullptr;
};

} // namespace gimp
