// The composite grid in PETSc: one DMDA per level (dof = dimension), composed (DMComposite) into
// the global Vec that TS advances, and this rank's window of every level.
//
// Each rank works on a window: the nodes within two level-0 cells of the level-0 cells it owns
// (particles are owned by the rank owning their level-0 cell). A VecScatter moves values between
// the global Vec and the window (insert forward, add in reverse), so P2G and G2P run on plain
// arrays and finer levels need no decomposition matching level 0.
#pragma once

#include "gimp/geometry/crack.hpp"
#include "gimp/geometry/crack_surface.hpp"
#include "gimp/grid/lattice.hpp"
#include "gimp/grid/stencils.hpp"

#include <petscdmcomposite.h>
#include <petscdmda.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <limits>
#include <type_traits>
#include <utility>
#include <vector>

namespace gimp {

/// This rank's window of nodes, all levels concatenated (x fastest within a level): their
/// slots, activity, regularity, coordinates and zones.
struct WindowNodes {
  // Window node data (all levels concatenated; x fastest within a level).
  PetscInt nWindow = 0;
  // Slots of the window arrays (D values each): the nWindow nodes, then one second velocity
  // field per cracked window node (docs/architecture.md). slotNode[s] is the window node of slot
  // s; crackSlot[n] the second slot of window node n, or -1. liveSlot[n] is crackSlot[n] where a
  // crack as it is now (not a growth reserve) comes within a particle's reach of node n's
  // support, so that a particle may join the second field (cracks::assignFields), else -1
  // (Grid::markLiveCracks; empty without cracked nodes).
  PetscInt nSlots = 0;
  std::vector<PetscInt> slotNode, crackSlot, liveSlot;
  std::vector<std::uint8_t> active, regular;
  std::vector<double> X, Y, Z; // node coordinates (Z empty in 2D)
  std::vector<double> zone;    // 2 D per node: Lx-, Lx+, Ly-, Ly+ (, Lz-, Lz+)
  /// Coordinates of the window nodes along axis a.
  const std::vector<double> &coordinates(int a) const { return a == 0 ? X : a == 1 ? Y : Z; }
};

/// The composite grid: its levels (Lattice), its DMs and this rank's window (WindowNodes).
template <int D> class Grid : public Lattice<D>, public WindowNodes {
public:
  using Index = LatticeIndex<D>;
  using Lattice<D>::levels;
  using Lattice<D>::origin;
  using Lattice<D>::unit;

  /// A node whose support (widened by a particle's reach) a crack cuts.
  struct CrackedNode {
    int k;
    Index i;
    PetscMPIInt owner; // the rank owning the node's level-0 cell
    PetscInt ownerPos; // its index among the cracked nodes of that owner
  };

  Grid() = default;
  Grid(const Grid &) = delete;
  Grid &operator=(const Grid &) = delete;
  ~Grid();

  /// Build the levels from level 0's cell size and the level boxes (boxes[0] the domain), the
  /// composite DM, this rank's window and its scatter, and the second fields of the nodes the
  /// cracks cut. Collective.
  PetscErrorCode create(MPI_Comm comm, double h0, const std::vector<LevelBox<D>> &boxes,
                        const std::vector<CrackOf<D>> &cracks = {});
  /// Back to an empty grid (its DMs destroyed), the crack reserves and cellWork kept: create() may
  /// build it again, from moved level boxes (levels that follow a point, solver/regrid.cpp).
  void clear();

  /// Disks (2D; balls in 3D) where cracks may grow, centre then radius: set before create(),
  /// their nodes get second fields as the nodes a crack cuts do (empty: none).
  std::vector<std::array<double, D + 1>> crackReserve;
  /// Regions where 3D cracks may grow in their planes: planar polygons whose nearby nodes get
  /// second fields as the nodes a crack cuts do (set before create(); empty: none).
  std::vector<CrackOf<D>> crackReserveSurfaces;

  /// The work of a leaf cell (centre, cell size): the particles it will hold. Set before
  /// create(), level 0 is split among the ranks so that each holds about the same work along
  /// every axis the ranks divide (balancedRanges); empty: PETSc's even split of the nodes.
  std::function<double(const double *centre, double h)> cellWork;

  /// The cracked nodes where a segment from a particle of half-size up to `reach` (along each
  /// axis) to the node can cross a crack as it is now (liveSlot), and the blocks of the
  /// stencils' compact path that hold none of them. create() marks them for reach h0 (every
  /// particle the checks allow); the solver marks them again when a crack grows and when the
  /// largest half-size calls for another reach (liveReachFor).
  void markLiveCracks(const std::vector<CrackOf<D>> &cracks, double reach);
  /// The reach of the last markLiveCracks.
  double liveReach() const { return liveReach_; }
  /// The reach for particles of half-size up to lmax: h0 / 2^k for the largest k >= 0 with
  /// h0 / 2^k >= lmax, so that it changes only when lmax passes a power of two of h0 (and is a
  /// function of lmax alone: a restart marks what the run it continues had marked).
  double liveReachFor(double lmax) const;

  /// Per axis, the work of the leaf cells (cellWork) summed per level-0 cell index along it.
  std::vector<std::vector<double>> workAlongAxes() const;

  DM dm = nullptr;         // DMComposite of the level DMDAs (and crackDm, with cracks)
  DM crackDm = nullptr;    // DMShell of the cracked nodes' second fields (dof D), or null
  std::vector<DM> da, da1; // per level: the DMDA (dof D) and its dof-1 twin (scalar output)

  /// Vectors on the window (sequential, dof D) and moves between them and a global Vec.
  /// With `from` > 0 a move covers levels from, from + 1, ... and the crack fields alone: the
  /// window slots from windowLevelStart(from) on and their global entries (on this rank, from
  /// localLevelStart(from) on); the rest of both Vecs is neither read nor written. Collective:
  /// every rank passes the same `from`.
  PetscErrorCode createWindowVec(Vec *v) const;
  PetscErrorCode toWindow(Vec global, Vec window, int from = 0) const; // insert
  /// Window values into the global Vec, combined by `mode`: ADD_VALUES sums every rank's window
  /// (the caller zeroes global first), INSERT_VALUES where every rank holding a slot has the
  /// same value, MAX_VALUES the largest (the caller sets global to -inf first).
  PetscErrorCode fromWindow(Vec window, Vec global, InsertMode mode, int from = 0) const;
  PetscErrorCode addFromWindow(Vec window, Vec global, int from = 0) const {
    return fromWindow(window, global, ADD_VALUES, from);
  }
  /// Sums made on the window that end in a global Vec (P2G, forces). startSum zeroes `global`
  /// on this rank from value zeroFrom on (-1: the levels from `from` on) and gives in *sum the
  /// Vec to add into on the levels from `from` on: the window, zeroed there, or `global` itself
  /// where the window is this rank's global array (one rank). endSum adds the window's sums over
  /// the ranks into `global` (nothing to do on one rank). The same sums, in the same order,
  /// either way.
  PetscErrorCode startSum(Vec window, Vec global, Vec *sum, int from = 0,
                          PetscInt zeroFrom = -1) const;
  PetscErrorCode endSum(Vec window, Vec global, int from = 0) const;
  /// The first value of level a's nodes in a window array: levels a, a + 1, ... and then the
  /// crack fields fill the rest of it.
  PetscInt windowLevelStart(int a) const { return D * levels[a].offset; }
  /// The first value of level a's nodes in this rank's part of a global Vec: levels a, a + 1,
  /// ... and then the crack fields fill the rest of it.
  PetscInt localLevelStart(int a) const { return localLevelStart_[a]; }
  /// Whether the window is this rank's global array, slot for slot (one rank): window value i
  /// is this rank's global value i.
  bool windowIsLocal() const { return windowIsLocal_; }
  /// Every cracked node, in the order of the composite's crack part (see crack_fields.cpp).
  const std::vector<CrackedNode> &crackedNodes() const { return cracked_; }

  /// Rank owning the level-0 cell containing the point x (D coordinates).
  PetscMPIInt ownerOf(const double *x) const;
  template <int E = D, std::enable_if_t<E == 2, int> = 0>
  PetscMPIInt ownerOf(double x, double y) const {
    const double p[2] = {x, y};
    return ownerOf(p);
  }
  /// The region of rank r's level-0 cells: low corner, then high corner (unbounded at the
  /// domain's faces).
  void ownedBox(PetscMPIInt r, double box[2 * D]) const;

  /// Window slot of level k's node i (which must lie in this rank's window).
  PetscInt windowSlot(int k, const PetscInt *i) const {
    const Level<D> &L = levels[k];
    PetscInt s = 0;
    for (int a = D - 1; a >= 0; --a)
      s = s * L.wn(a) + (i[a] - L.w0[a]);
    return L.offset + s;
  }

  /// What a build notes of its particles as it reads them (buildStencils' `seen`, on success):
  /// the bounding box [lo, hi] of their domains [x - l, x + l] (2D simd::minOf(x - l, lo), 3D
  /// std::min(lo, x - l)), and with `watch` the particles whose domain widened by `reach` meets
  /// the box `near` (in order). A rate class's start reads them without a second pass over its
  /// particles.
  struct BuildSeen {
    bool watch = false;
    BoxOf<D> near{};
    double reach = 0;
    double lo[D], hi[D];
    std::vector<PetscInt> nearParticles;
    void start() {
      for (int a = 0; a < D; ++a)
        lo[a] = std::numeric_limits<double>::infinity(), hi[a] = -lo[a];
      nearParticles.clear();
    }
  };
  /// Stencils of n particles (positions x, half-sizes l; D values each). Returns false, with s
  /// unchanged past the particles done, when a particle is larger than a level-0 cell (the
  /// caller reports it collectively). With `compact` a particle inside one level's regular
  /// block keeps a block instead of rows (grid/stencils.hpp). With `patterns` (3D: the rate
  /// classes of a per-level step, which build the same particles' stencils at every sub-step)
  /// appendNodes keeps the node patterns it reads (NodePattern) for the next particles and
  /// builds; the same stencils.
  bool buildStencils(PetscInt n, const double *x, const double *l, Stencils<D> &s,
                     bool compact = false, bool lanes = false, bool patterns = false,
                     BuildSeen *seen = nullptr) const;

  /// CPDI stencils (Sadeghirad et al. 2011, 2013) of n particles whose domains are the
  /// quadrilaterals (2D) or hexahedra (3D) of their 2^D corners (D 2^D values each, in the order
  /// of grid/cpdi_cells.hpp): general entries, S_ip = (1/A) sum_c w_c N_i(x_c) and
  /// grad S_ip = (1/A) sum_c N_i(x_c) G_c with w_c the integral of the bi/trilinear map's corner
  /// function over the cell, G_c that of its gradient, A the cell's area or volume, N_i the
  /// composite grid's point shape functions. Returns null, or why it could not (a corner outside
  /// the grid or the rank window, a collapsed or inverted domain), with s unchanged past the
  /// particles done.
  const char *buildCpdiStencils(PetscInt n, const double *corners, Stencils<D> &s) const;
  /// The point shape functions of the active nodes at x (D coordinates; the tent functions of
  /// Eq. 14 with the zones of transition and edge nodes): appends (slot, N) with N > 0 to `out`;
  /// returns their sum (1 inside the grid and the window).
  double pointShapes(const double *x, std::vector<std::pair<PetscInt, double>> &out) const;
  template <int E = D, std::enable_if_t<E == 2, int> = 0>
  double pointShapes(double x, double y, std::vector<std::pair<PetscInt, double>> &out) const {
    const double p[2] = {x, y};
    return pointShapes(p, out);
  }

  /// buildCpdiStencils' entries of a particle whose corners c lie among one level's regular
  /// nodes that no finer level reaches: its nodes (at most 3^D) and their weights at each corner
  /// (cw, 2^D per node), the count; -1 where that does not hold (the general path then).
  int regularCornerEntries(const double *c, PetscInt *node, double *cw) const;

  /// The coarsest level whose nodes can reach a particle at x with half-sizes l: the finest
  /// level whose box (closed) holds the particle (0 if none).
  int coarsestReaching(const double *x, const double *l) const;

private:
  /// buildStencils with (Notes) and without a BuildSeen: the single step's build does not test
  /// for one per particle.
  template <bool Notes>
  bool buildStencilsNoting(PetscInt n, const double *x, const double *l, Stencils<D> &s,
                           bool compact, bool lanes, bool patterns, BuildSeen *seen) const;
  void destroyPetsc();
  /// The DMs, the window, its nodes, the crack fields and the scatter.
  PetscErrorCode build(MPI_Comm comm, const std::vector<CrackOf<D>> &cracks);
  /// Level-0 ownership and this rank's window of every level.
  PetscErrorCode setWindow();
  /// Level 0's DMDA again with the same rank layout and its nodes split by cellWork.
  PetscErrorCode balanceLevel0(MPI_Comm comm);
  /// Every cracked node of the grid, in an order every rank agrees on (collective-free).
  std::vector<CrackedNode> findCrackedNodes(const std::vector<CrackOf<D>> &cracks) const;
  /// The DMShell of the second fields, its window slots and their composite indices.
  PetscErrorCode addCrackFields(MPI_Comm comm, const std::vector<CrackOf<D>> &cracks);
  /// Positions, activity, zones and regularity of the window's nodes.
  void fillWindowNodes();
  /// The scatter between the composite global Vec and the window.
  PetscErrorCode createScatter(MPI_Comm comm);

  /// The candidate nodes of one level for one particle: [i0, i1] per axis of the window,
  /// whether the particle's centre is inside the level's box, and whether they form a regular
  /// 3^D block with closed-form weights.
  struct Reach {
    PetscInt i0[D] = {}, i1[D] = {};
    bool inside = false, threeNodeBlock = false,
         fourNodeBlock = false; // four: 2D, a regular 4^D block
  };
  /// Level q's candidate nodes for the particle (q at least coarsestReaching's level).
  bool levelReach(int q, const double *x, const double *l, Reach &r) const;
  /// The block of level q (coarsestReaching's level) of a particle that no other level reaches
  /// and whose candidates there form a regular block: its side (3, or 4 in 2D for a half-size
  /// between h/2 and h), with its first node in i0; 0 where that cannot be settled in a few
  /// comparisons (levelReach decides then). Where it is not 0, buildStencils' general path gives
  /// the same block.
  int soleBlock(int q, const double *x, const double *l, PetscInt *i0) const;
  /// (2D, with lanes: transfer/lane_loops.hpp) Particles k .. k+3 (k a multiple of 4, s.laneGroup
  /// sized for the particles) as lane group k / 4: 3-node blocks of one level, when soleBlock
  /// gives each of them side 3 on the same level, their factors computed as setBlock computes
  /// them, in four lanes (AVX2), bit for bit, and stored factor-major (LaneBlocks); the group
  /// marked in s.laneGroup. False, with nothing written, otherwise.
  bool blockRun(PetscInt k, const double *x, const double *l, Stencils<D> &s) const;
  /// (3D, with lanes) Particle k as level q's 3-node block when soleBlock gives it side 3 there,
  /// with its x, y and z in lanes (AVX2): soleBlock's tests and setBlock's factors in their
  /// arithmetic, bit for bit. False, with nothing written, otherwise.
  bool blockLanes(int q, PetscInt k, const double *x, const double *l, Stencils<D> &s) const;
  /// Particle k keeps level q's 3-node block from node i0.
  void setBlock(int q, const PetscInt *i0, const double *x, const double *l, Stencils<D> &s,
                PetscInt k) const;
  /// Particle k keeps level q's 4-node block from node i0 (2D): the weights of appendNodes to
  /// round-off (shape::fourNodeWeights).
  void setBlock4(int q, const PetscInt *i0, const double *x, const double *l, Stencils<D> &s,
                 PetscInt k) const;
  /// Level q's entries of a particle as rows (from m), or with `block` as that level block
  /// (LevelBlock: no rows written). Returns 1 when the block was written, 0 when no node of the
  /// level overlaps the particle (or rows were written), -1 when the entries are not a level
  /// block (not a tensor product, wider than 4 nodes along an axis, or with a live cracked node).
  int appendThreeNodeBlock(int q, const Reach &r, const double *x, const double *l, Stencils<D> &s,
                           size_t &m, LevelBlock<D> *block = nullptr) const;
  using NodePattern = gimp::NodePattern<D>;
  /// The patterns of the boxes met last, by their key (a hash, one pattern per entry). What they
  /// read changes with the window's nodes (fillWindowNodes), the second fields (addCrackFields)
  /// and the live cracked nodes (markLiveCracks): each of those forgets them all.
  struct PatternCache {
    static constexpr int kBits = 14, kSize = 1 << kBits; // (1 MB in 3D, whatever the particles)
    /// The table, made (empty) at the first call: only a build with patterns pays for it.
    void ready() {
      if (slots.empty()) slots.resize(kSize);
    }
    /// The entry that holds key, or the one of its pair (two ways per hash, so that two boxes of
    /// one hash do not evict each other at every use) to put it in: the one used less recently.
    NodePattern &entry(std::uint64_t key) {
      const std::uint32_t at =
          static_cast<std::uint32_t>(2 * ((key * 0x9E3779B97F4A7C15ull) >> (65 - kBits)));
      NodePattern *pair = &slots[at];
      const int way = pair[1].key == key || (pair[0].key != key && pair[0].recent);
      pair[way].recent = true;
      pair[1 - way].recent = false;
      return pair[way];
    }
    /// Every pattern read so far is void (the table's and those the stencils keep).
    void forget() {
      for (NodePattern &p : slots)
        p.key = ~std::uint64_t{0};
      ++generation;
    }
    std::vector<NodePattern> slots;
    // Which state of which grid the patterns read (Stencils::patternGeneration): counted by
    // forget() from the clock's reading at construction, so that another grid's count, even at
    // the same address, is not this one's.
    std::uint64_t generation =
        static_cast<std::uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count());
    // A build's particle (buildStencils sets them): its patterns of the last build, [last,
    // lastEnd), the next of them to try, and where this build's go (Stencils::patterns).
    const NodePattern *last = nullptr, *lastEnd = nullptr;
    std::vector<NodePattern> *out = nullptr;
  };
  /// (scratch: room for 6 D maxRange doubles, maxRange at least the candidates along an axis)
  /// (with `block`, a level of more than 4 candidates along an axis gives -1)
  /// (with `cache`, a box of at most 4 candidates per axis whose pattern is a tensor product
  /// takes appendFromPattern: the same entries, factors and block)
  int appendNodes(int q, const Reach &r, const double *x, const double *l, double *scratch,
                  PetscInt maxRange, Stencils<D> &s, size_t &m, LevelBlock<D> *block = nullptr,
                  PatternCache *cache = nullptr) const;
  /// The pattern of level q's candidate box r (trimmed as appendNodes trims it), from the cache
  /// or read from the window's nodes into it.
  const NodePattern &patternOf(int q, const Reach &r, PatternCache &cache) const;
  /// appendNodes' result from a tensor pattern p: per axis the overlaps of each candidate index,
  /// the entries, then the 1D factors of the indices that hold one.
  int appendFromPattern(const NodePattern &p, int q, const Reach &r, const double *x,
                        const double *l, Stencils<D> &s, size_t &m, LevelBlock<D> *block) const;

  mutable PatternCache patterns_; // appendNodes' node patterns
  // The distinct zone values of the window's active nodes, ascending (NodePattern::Z); empty
  // when there are more than 255 (appendNodes then reads every node).
  std::vector<double> zoneValues_;
  static constexpr std::uint8_t kActive = 1, kRegular = 2;
  std::vector<std::uint8_t> flags_; // active and regular in one byte per window node
  // The 3^D block of one level from this node is regular for its particles: its nodes active,
  // with zone h on every side a block particle can overlap (fillWindowNodes); fourNodeBlocks_
  // the same for the 4^D block (2D).
  std::vector<std::uint8_t> threeNodeBlocks_, fourNodeBlocks_;
  // With cracks, the same less the blocks that hold a live cracked node (liveSlot): the compact
  // path of buildStencils reads these (a particle there keeps rows, which cracks::assignFields
  // re-addresses); empty without a cracked node in the window.
  std::vector<std::uint8_t> crackFreeThree_, crackFreeFour_;
  double liveReach_ = 0; // the reach liveSlot was marked for
  const std::uint8_t *compactThree() const {
    return crackFreeThree_.empty() ? threeNodeBlocks_.data() : crackFreeThree_.data();
  }
  const std::uint8_t *compactFour() const {
    return crackFreeFour_.empty() ? fourNodeBlocks_.data() : crackFreeFour_.data();
  }
  std::vector<double> outwardReach_; // per level: the largest zone of its box's boundary nodes
  std::array<std::vector<PetscInt>, D> own_; // level-0 node ownership: first node of each rank
                                             // column per axis
  std::vector<CrackedNode> cracked_;         // every cracked node (empty without cracks)
  std::vector<PetscInt> crackedOfSlot_;      // index into cracked_ of each second-field slot
  std::vector<PetscInt> crackCount_;         // cracked nodes owned by each rank
  VecScatter scatter_ = nullptr;
  bool windowIsLocal_ = false; // the window is this rank's global array (one rank): moves copy
  Vec windowTemplate_ = nullptr;
  std::vector<PetscInt> localLevelStart_; // per level, then the end: localLevelStart
  /// The window slots' composite block indices (the scatter's, slot by slot) and, with
  /// localStart, localLevelStart_. Collective.
  PetscErrorCode compositeBlocks(MPI_Comm comm, std::vector<PetscInt> &blocks,
                                 std::vector<PetscInt> *localStart) const;
  /// The scatter of levels from, from + 1, ... (made at its first use) and its window Vec, which
  /// borrows the window array of each move.
  PetscErrorCode suffixScatter(int from, VecScatter *sc, Vec *w) const;
  /// toWindow (SCATTER_FORWARD) and fromWindow (SCATTER_REVERSE).
  PetscErrorCode move(Vec window, Vec global, InsertMode mode, ScatterMode dir, int from) const;
  mutable std::vector<VecScatter> suffixScatter_;
  mutable std::vector<Vec> suffixWindow_;
};

/// v's values [from, to) on this rank set to zero (to < 0: to the end of this rank's part).
PetscErrorCode zeroValues(Vec v, PetscInt from, PetscInt to = -1);

extern template class Grid<2>;
extern template class Grid<3>;

/// Ownership ranges of `nodes` lattice nodes among np ranks along one axis, each rank's first
/// node where the cumulative work of the cells before it (work[i]: cell i, between nodes i and
/// i + 1) is nearest r / np of the total; every rank at least one node.
std::vector<PetscInt> balancedRanges(const std::vector<double> &work, PetscInt nodes, PetscInt np);

} // namespace gimp
