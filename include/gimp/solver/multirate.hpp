// The multi-rate step of -gimp_multirate (docs/method.md, "Multi-rate time steps per level").
//
// One call advances R = levels[0].step fine steps of dt (one TSStep each, on the same composite
// momentum as the single-rate step). The particles whose stencils reach level c at most form
// class c and step every levels[c].step fine steps: class c starts at the sub-steps j with
// j mod m_c = 0 (its stencils, its P2G onto the nodes, its forces times m_c as one impulse) and
// ends at the sub-steps with (j + 1) mod m_c = 0 (G2P from what the nodes did since its start,
// its stress over m_c dt, and the removal of the momentum its particles took). Between its start
// and end its mass and momentum ride on the nodes with every other class's, so mass and momentum
// are exact. The phases are the single-rate step's (Step), run on each class's slice of the
// particles.
#pragma once

#include "gimp/solver/step.hpp"

#include <array>
#include <vector>

namespace gimp {

/// Values of this rank's part of a global Vec (or of a window): disjoint stretches [from, to),
/// in order. A rate class's nodal sums are zero outside its stretches (RateClasses::values).
using Stretches = std::vector<std::array<PetscInt, 2>>;
/// The union of two sets of stretches, and the values of a that are not in b (one walk along
/// each: both in order and disjoint).
Stretches unite(const Stretches &a, const Stretches &b);
Stretches minus(const Stretches &a, const Stretches &b);
/// v = 0 on the stretches.
PetscErrorCode zeroStretches(Vec v, const Stretches &at);
/// The sums over every rank of a_i y_i and b_i y_i on this rank's values `at`, each in their
/// order, into z[0] and z[1]: VecDot's sums where a y and b y are zero elsewhere (its BLAS sums
/// in order too, so the two agree on one rank).
PetscErrorCode dotsOn(Vec a, Vec b, Vec y, const Stretches &at, PetscScalar *z);

/// Which particles step how: class c holds this rank's particles [begin[c], begin[c + 1]).
template <int D> struct RateClasses {
  int n = 0;                      // classes: one per level
  std::vector<PetscInt> every;    // fine steps per step of class c (levels[c].step)
  std::vector<PetscInt> begin;    // the classes' ranges of this rank's particles
  std::vector<PetscInt64> size;   // particles of class c on all ranks (0: the class is skipped)
  std::vector<PetscInt> switched; // particles of class c that were in another class before
  std::vector<double> kickScale;  // per particle of this coarse step: its first kick's weight
                                  // over its class's step, (m_old + m_new) / (2 m_new) (empty
                                  // when no particle switched)
  std::vector<Stencils<D>> st;    // class c's stencils, from its last start
  std::vector<PetscInt> start;    // the sub-step of class c's last start
  // The coarsest level class c's stencils reach (on every rank), from its last start: its nodal
  // values lie on the levels from there on (values), and the moves of its fields between the
  // window and the global Vecs cover those levels (Grid::toWindow: a scatter of them alone).
  std::vector<int> from;
  // Where class k's nodal values lie in this rank's part of a global Vec, from its last start:
  // on one rank the nodes of level `from` that its particles' domains may reach (a box of them,
  // row by row along x) and the finer levels after them, else every value from that level's
  // start on (Grid::localLevelStart). Its sums are zero elsewhere, and its nodal passes skip the
  // rest: they cost what the class's own box of nodes holds, however wide the coarse grid.
  std::vector<Stretches> values;
  std::vector<char> live; // a class stepping every sub-step: inc holds its increments (else dt a)
  // With external forces, for the work of class c's external impulse: the power of its force
  // (ClassSums::fext) before and after the impulse, summed, and the impulse's factor (m_c, times
  // the kick weight of its start).
  std::vector<double> extStart, extScale;
  // Impulse rule with external forces: whether class c's particles carry any (a traction face,
  // a body force, penalty conditions; on any rank, from its coarse start), and whether its
  // ClassSums::fext is zero (a class without them skips its external force and work).
  std::vector<char> loaded, fextZero;
};

/// Global, per class (dof layout of the momentum): what it brought to the nodes at its start and
/// what the nodes did since.
struct ClassSums {
  ClassSums() = default;
  ClassSums(const ClassSums &) = delete;
  ClassSums &operator=(const ClassSums &) = delete;
  ~ClassSums();
  // Its mass (component 0) and momentum at its start, the sum of the grid velocity increments
  // and of the grid velocities since.
  std::vector<Vec> mass, mom, inc, vsum;
  // Node rule only: its force at its last start (internal and external, times that step's kick
  // weight) and that force at the start of each node's anchor step (base). With external forces
  // (either rule) the external part on its own (fext; the impulse rule's without the kick weight)
  // and, node rule, its base.
  std::vector<Vec> force, base, fext, baseExt;
  // Node rule: each node's rate, the step of the slowest class whose mass is on it now (its
  // anchor; every dof), set where a class starts.
  Vec nodeRate = nullptr;
  // With cracks, per class on the window: its crack faces from its start (Contact::faces; its
  // stencils and positions do not change until its end).
  std::vector<Vec> faces;
  // Per class: mass and mom zero everywhere (its end zeroed them as it read them last).
  std::vector<char> clean;
};

/// Scratch vectors of the coarse step.
struct RateScratch {
  RateScratch() = default;
  RateScratch(const RateScratch &) = delete;
  RateScratch &operator=(const RateScratch &) = delete;
  ~RateScratch();
  Vec taken = nullptr, field = nullptr;  // global: what the ending classes took, a field
  Vec corr = nullptr, corrSum = nullptr; // MUSL: a class's re-projection correction, their sum
  Vec fieldW = nullptr, meanW = nullptr, forceW = nullptr; // window
  Stretches dirty; // taken and corrSum: where they may not be zero
  // forceW and corr zero everywhere: their passes zero them where they wrote, after use
  bool forceClean = false, corrClean = false;
  // One class ends and nothing reads the grid velocity (momentum) between its MUSL correction
  // and the sub-step's end: the correction adds its share to nodal.vel (takes what the class
  // took from nodal.P) in its own pass, not through corrSum (taken) (MultiRate::endClasses).
  bool velInCorrection = false, momentumInCorrection = false;
  // The sub-step's nodes (MultiRate::gridUpdate): the values the starting classes' forces reach
  // and those startNodes swept; where the acceleration may not be zero; with damping the values
  // where P may be nonzero (every class's), which the damping moves.
  Stretches forced, swept, accAt, massive;
  // With damping on those values: P . v and rhs . v after the update (Step::work's sums).
  std::array<PetscScalar, 2> dampingDots{};
};

template <int D> class MultiRate {
public:
  MultiRate(RunState<D> &s, Step<D> &step) : s_(s), step_(step) {}
  /// The classes and their vectors (like: a global nodal Vec).
  PetscErrorCode create(Vec like);
  /// R fine steps, up to the checks at the coarse step's end; `done` is the step and time it
  /// reached.
  PetscErrorCode run(StepClock &done);
  /// The classes' stencils' memory back (every class ended with the coarse step).
  void releaseStencils() {
    for (Stencils<D> &st : r_.st)
      st.release();
  }

private:
  /// Each particle's class, the swarm ordered by class, the slices and the kick weights.
  PetscErrorCode classify(PetscInt step);
  /// Sub-step j: the classes that start (stencils, P2G), the total mass and mask.
  PetscErrorCode startClasses(ParticleView<D> &p, PetscInt j);
  /// A starting class's stencils, P2G and crack faces (startClasses, class k); `changed` holds
  /// the values of its mass and momentum that the start changed.
  PetscErrorCode startClass(ParticleView<D> &p, int k, PetscInt j, Stretches &changed);
  /// Sub-step j, on this rank's values `sweep` (elsewhere all is as it was), in one pass: the
  /// starting classes' momenta added to P, the summed mass of the classes, with the node rule
  /// the node rates, the masks, P masked and the velocity.
  PetscErrorCode startNodes(const Stretches &sweep, PetscInt j);
  /// The starting classes' forces, each times its step in sub-steps, into nodal.f.
  PetscErrorCode classForces(const ParticleView<D> &p, const StepClock &c, PetscInt j,
                             StartPower &power);
  /// RateClasses::loaded at a coarse start (impulse rule with external forces; collective).
  PetscErrorCode loadedClasses(const ParticleView<D> &p);
  /// The node rule's delivery of class k's force (and external force) at sub-step j.
  PetscErrorCode deliverNodeRule(int k, PetscInt j, double kick, bool external);
  /// Sub-step j's grid update: TS euler on every node (Step::gridUpdate); or, where the nodes
  /// outside the starting classes' values feel no force but the damping's (one rank, the
  /// impulse rule, no cracks), the same update on those values (and with damping on the values
  /// where P may be nonzero) alone, TS's clock moved on by a step.
  /// With damping there it forms the damping's power at the sub-step's start (power) and its
  /// sums for Step::work (RateScratch::dampingDots) in the same pass.
  PetscErrorCode gridUpdate(const StepClock &c, bool cracked, StartPower &power);
  /// Whether gridUpdate may keep to the starting classes' values (sparse_; at a coarse start).
  PetscErrorCode decideSparseUpdate();
  /// After the grid update with cracks: contact on the new velocities, the momentum follows.
  PetscErrorCode contactAfterUpdate(const StepClock &c);
  /// After the grid update of sub-step j: each class's sums since its start.
  PetscErrorCode accumulate(const StepClock &c, PetscInt j);
  /// What class k's particles take from the nodes at their G2P (takenBy's rule), read from
  /// its sums: flip (p_k + m_k ds inc_k) + (1 - flip) m_k v per component (APIC: flip 0).
  struct Taken {
    Vec vv, mv, pv, dv;
    double flip, ds;
    const PetscScalar *v = nullptr, *m = nullptr, *p = nullptr, *d = nullptr;
    // With get(true) the class's mass and momentum writable too, to zero them after their last
    // read (the class's end: zero() node by node).
    PetscScalar *mw = nullptr, *pw = nullptr;
    PetscErrorCode get(bool own = false);
    PetscErrorCode restore();
    /// Node value i's mass and momentum zeroed (get(true); the mass in component 0).
    void zero(PetscInt i) const {
      mw[i] = 0.0;
      for (int q = 0; q < D; ++q)
        pw[i + q] = 0.0;
    }
    /// Component q of node value i (i a node's first component), Flip: flip > 0 (the passes
    /// over a class's values take the branch once, outside their loops).
    template <bool Flip> double at(PetscInt i, int q) const {
      // (with flip 0 the increments are not summed: not read)
      if constexpr (Flip)
        return flip * (p[i + q] + m[i] * ds * d[i + q]) + (1.0 - flip) * m[i] * v[i + q];
      else
        return m[i] * v[i + q];
    }
  };
  Taken taken(int k, double flip, double dt) const;
  /// What class k's particles take from the nodes at their G2P, into (or added to) out.
  /// With zero (the class's end) its mass and momentum are zeroed in the same pass.
  PetscErrorCode takenBy(int k, double flip, double dt, Vec out, bool add, bool zero = false);
  /// After the grid update of sub-step j: the ending classes' G2P, stress and momentum removal.
  /// With `tally` (the coarse step's last sub-step, where every class ends and its stress
  /// update is its particles' last change), each class's particles are tested as
  /// Step::checks would test them, while they are in cache; indices are the swarm's.
  PetscErrorCode endClasses(ParticleView<D> &p, const StepClock &c, PetscInt j,
                            const StartPower &power, typename Step<D>::CheckTally *tally);
  /// After the grid update of sub-step j: the work of the starting classes' external impulses
  /// (booked at their classes' ends, with the ending classes' MUSL correction).
  PetscErrorCode externalWork(const StepClock &c, PetscInt j, const std::vector<int> &ending);
  /// Every class ends with a FLIP/PIC blend: the momentum no particle took goes to them.
  PetscErrorCode spreadRemainder(const std::vector<int> &ending, const StepClock &c, double flip);
  /// Class k's G2P and stress at its end (the e-th of the ending classes), its particles'
  /// test added to `tally` when not null (endClasses).
  PetscErrorCode endClass(ParticleView<D> &p, const StepClock &c, int k, size_t e, double flip,
                          typename Step<D>::CheckTally *tally);
  /// MUSL: class k's re-projection correction and the stress velocity into meanW; what it took
  /// (takenBy's rule, in the same pass) added to taken.
  PetscErrorCode correction(const StepClock &c, int k, size_t e, double flip);
  /// y += a x on this rank's values `at` (a = +-1 or a class's step count, a power of 2: exact as
  /// VecAXPY; onZero: y = 0 + a x, the sum on a zero y), and x zeroed there in the same pass (it
  /// is read there no more).
  static PetscErrorCode addOnAndZero(Vec y, double a, Vec x, const Stretches &at,
                                     bool onZero = false);
  /// The coarsest level that class k's particles reach, on every rank (RateClasses::from), and
  /// where its nodal values lie (RateClasses::values), from the bounding box [lo, hi] of their
  /// domains on this rank (any: it holds a particle).
  PetscErrorCode classReach(const double *lo, const double *hi, bool any, int k);
  /// Class k's values in a window of nw values (RateClasses::values where the window is the
  /// global array, else every value from its level on).
  Stretches windowValues(int k, PetscInt nw) const;

  RunState<D> &s_;
  Step<D> &step_;
  RateClasses<D> r_;
  ClassSums sums_;
  RateScratch scratch_;
  bool sparse_ = false;              // (decideSparseUpdate)
  std::vector<int> cls_;             // (classify: each particle's class; kept for its room)
  typename Grid<D>::BuildSeen seen_; // (startClass: what its build notes; kept for its room)
};

} // namespace gimp
