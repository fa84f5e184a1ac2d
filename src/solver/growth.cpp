// Crack growth in the run (-gimp_crack_growth mts; docs/method.md, *Crack growth*): the grid's
// second fields where the tips (2D) or fronts (3D) may grow, the growth checks, and what follows a
// grown crack. What derives from the polylines and polygons: the tip frames and measures
// (measureTips and measureFronts read the cracks each time), the J domains and front tubes
// (Scene::jDomain: updateJDomains, updateFrontDomains), the contact directions of the cracked
// nodes (Contact::setup) and, each step, which field of a cracked node a particle joins
// (assignFields), the corners' fields and the separation measure: those read the cracks as they
// are.
#include "gimp/cracks/growth.hpp"
#include "gimp/solver/solver.hpp"

namespace gimp {

template <int D> void Solver<D>::reserveCrackGrowth() {
  if constexpr (D == 2)
    for (const TipGrowth &g : s_.sc.tipGrowth)
      s_.grid.crackReserve.push_back({g.origin[0], g.origin[1], g.length});
  else
    for (const FrontGrowth &g : s_.sc.frontGrowth)
      s_.grid.crackReserveSurfaces.push_back(cracks::growthReach(g.start, g.length));
}

template <int D> PetscErrorCode Solver<D>::followCracks(double t) {
  if (s_.sc.growth == Growth::None) return PETSC_SUCCESS;
  if constexpr (D == 2)
    updateJDomains(s_.sc);
  else
    updateFrontDomains(s_.sc);
  s_.grid.markLiveCracks(s_.sc.cracks, s_.grid.liveReach());
  setupContact(t);
  return PETSC_SUCCESS;
}

template <int D> void Solver<D>::setupContact(double t) {
  // (2D: the increments being released follow from the growth records and the polylines alone;
  // 3D: from the polygons before the advances, which the checkpoint keeps; so a restart or a
  // regrid finds them again)
  if constexpr (D == 2)
    step_.contact().setup(s_.grid, s_.sc.cracks, cracks::releasing(s_.sc, s_.measures.growth, t),
                          s_.sc.growthRelease);
  else
    step_.contact().setup(s_.grid, s_.sc.cracks, cracks::releasing(s_.sc, t), s_.sc.growthRelease);
}

namespace {

/// Rank 0's values of the measures that decide growth, on every rank. The reduced sums are the
/// same on every rank in the MPI libraries in use, but MPI does not promise it: rank 0's values
/// decide, so every rank grows the same crack.
template <class M, size_t N>
PetscErrorCode fromRankZero(MPI_Comm comm, std::vector<M> &ms, double M::*const (&fields)[N]) {
  std::vector<double> decide;
  for (const M &m : ms)
    for (double M::*f : fields)
      decide.push_back(m.*f);
  PetscCallMPI(MPI_Bcast(decide.data(), static_cast<int>(decide.size()), MPI_DOUBLE, 0, comm));
  size_t q = 0;
  for (M &m : ms)
    for (double M::*f : fields)
      m.*f = decide[q++];
  return PETSC_SUCCESS;
}

} // namespace

template <int D> PetscErrorCode Solver<D>::growCracks(PetscInt step, double t) {
  RunState<D> &s = s_;
  if (s.sc.growth == Growth::None || s.status.failed) return PETSC_SUCCESS;
  if (!dueIn(step - s.stride() + 1, step + 1, s.sc.growthInterval)) return PETSC_SUCCESS;
  PetscCall(PetscLogStagePush(s.stages.output));
  std::vector<std::string> stops;
  std::vector<cracks::GrowthRecord> grown;
  // The history row of this step measured the same particles: its measures are this check's.
  const bool row = s.lastCrackRow.step == step;
  ParticleView<D> p;
  PetscCall(p.get(s.sw));
  if constexpr (D == 2) {
    std::vector<cracks::TipMeasure> tips;
    if (row)
      tips = s.lastCrackRow.tips;
    else
      PetscCall(cracks::measureTips(s.comm, s.sc, s.grid, p, tips));
    PetscCall(p.restore(s.sw));
    static double cracks::TipMeasure::*const fields[] = {
        &cracks::TipMeasure::G_J, &cracks::TipMeasure::KI_J, &cracks::TipMeasure::KII_J};
    PetscCall(fromRankZero(s.comm, tips, fields));
    grown = cracks::growTips(s.sc, tips, t, stops);
  } else {
    std::vector<cracks::FrontMeasure> front;
    const cracks::FrontDomain dom = cracks::frontDomain(s.sc);
    if (row)
      front = s.lastCrackRow.front;
    else
      PetscCall(cracks::measureFronts(s.comm, s.sc.cracks, s.sc.materialAt(dom.at.data()), p,
                                      dom.spacing, s.sc.jDomain, dom.R, dom.mirrors, front));
    PetscCall(p.restore(s.sw));
    static double cracks::FrontMeasure::*const fields[] = {
        &cracks::FrontMeasure::G, &cracks::FrontMeasure::KI, &cracks::FrontMeasure::KII,
        &cracks::FrontMeasure::KIII, &cracks::FrontMeasure::R};
    PetscCall(fromRankZero(s.comm, front, fields));
    grown = cracks::growFronts(s.sc, front, t, stops);
  }
  for (const std::string &line : stops)
    PetscCall(PetscPrintf(s.comm, "gimp: warning: %s\n", line.c_str()));
  for (const cracks::GrowthRecord &r : grown) {
    s.measures.growth.push_back(r);
    PetscCall(PetscInfo(nullptr,
                        "step %" PetscInt_FMT ": crack %d %s %d grows to %.9g,%.9g,%.9g (G %.6g "
                        "J/m^2, kink %.4g deg)\n",
                        step, r.crack, D == 2 ? "tip" : "front point", r.end, r.x[0], r.x[1],
                        r.x[2], r.G, r.kink));
  }
  if (!grown.empty()) PetscCall(followCracks(t));
  PetscCall(PetscLogStagePop());
  return PETSC_SUCCESS;
}

template void Solver<2>::reserveCrackGrowth();
template void Solver<3>::reserveCrackGrowth();
template PetscErrorCode Solver<2>::followCracks(double);
template PetscErrorCode Solver<3>::followCracks(double);
template void Solver<2>::setupContact(double);
template void Solver<3>::setupContact(double);
template PetscErrorCode Solver<2>::growCracks(PetscInt, double);
template PetscErrorCode Solver<3>::growCracks(PetscInt, double);

} // namespace gimp
