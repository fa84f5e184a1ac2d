// Crack growth in the run (2D, -gimp_crack_growth mts; docs/method.md, *Crack growth*): the
// grid's second fields where the tips may grow, the growth checks, and what follows a grown crack.
// What derives from the polylines: the tip frames and measures (measureTips reads the polylines
// each time), the J domains (Scene::jDomain: updateJDomains), the contact directions of the
// cracked nodes (Contact::setup) and, each step, which field of a cracked node a particle joins
// (assignFields), the corners' fields and the separation measure: those read the polylines as
// they are.
#include "gimp/cracks/growth.hpp"
#include "gimp/solver/solver.hpp"

namespace gimp {

template <int D> void Solver<D>::reserveCrackGrowth() {
  if constexpr (D == 2)
    for (const TipGrowth &g : s_.sc.tipGrowth)
      s_.grid.crackReserve.push_back({g.origin[0], g.origin[1], g.length});
}

template <int D> PetscErrorCode Solver<D>::followCracks() {
  if constexpr (D == 2) {
    if (s_.sc.growth == Growth::None) return PETSC_SUCCESS;
    updateJDomains(s_.sc);
    step_.contact().setup(s_.grid, s_.sc.cracks);
  }
  return PETSC_SUCCESS;
}

template <int D> PetscErrorCode Solver<D>::growCracks(PetscInt step, double t) {
  if constexpr (D == 2) {
    RunState<2> &s = s_;
    if (s.sc.growth == Growth::None || s.status.failed) return PETSC_SUCCESS;
    if (!dueIn(step - s.stride() + 1, step + 1, s.sc.growthInterval)) return PETSC_SUCCESS;
    PetscCall(PetscLogStagePush(s.stages.output));
    std::vector<cracks::TipMeasure> tips;
    ParticleView<2> p;
    PetscCall(p.get(s.sw));
    PetscCall(cracks::measureTips(s.comm, s.sc, s.grid, p, tips));
    PetscCall(p.restore(s.sw));
    // The reduced sums are the same on every rank in the MPI libraries in use, but MPI does not
    // promise it: rank 0's values decide, so every rank grows the same crack.
    std::vector<double> decide;
    for (const cracks::TipMeasure &m : tips)
      decide.insert(decide.end(), {m.G_J, m.KI_J, m.KII_J});
    PetscCallMPI(MPI_Bcast(decide.data(), static_cast<int>(decide.size()), MPI_DOUBLE, 0, s.comm));
    for (size_t q = 0; q < tips.size(); ++q) {
      tips[q].G_J = decide[3 * q];
      tips[q].KI_J = decide[3 * q + 1];
      tips[q].KII_J = decide[3 * q + 2];
    }
    std::vector<std::string> stops;
    const std::vector<cracks::GrowthRecord> grown = cracks::growTips(s.sc, tips, t, stops);
    for (const std::string &line : stops)
      PetscCall(PetscPrintf(s.comm, "gimp: warning: %s\n", line.c_str()));
    for (const cracks::GrowthRecord &r : grown) {
      s.measures.growth.push_back(r);
      PetscCall(PetscInfo(nullptr,
                          "step %" PetscInt_FMT ": crack %d tip %d grows to %.9g,%.9g (G %.6g "
                          "J/m^2, kink %.4g deg)\n",
                          step, r.crack, r.end, r.x[0], r.x[1], r.G, r.kink));
    }
    if (!grown.empty()) PetscCall(followCracks());
    PetscCall(PetscLogStagePop());
  }
  return PETSC_SUCCESS;
}

template void Solver<2>::reserveCrackGrowth();
template void Solver<3>::reserveCrackGrowth();
template PetscErrorCode Solver<2>::followCracks();
template PetscErrorCode Solver<3>::followCracks();
template PetscErrorCode Solver<2>::growCracks(PetscInt, double);
template PetscErrorCode Solver<3>::growCracks(PetscInt, double);

} // namespace gimp
