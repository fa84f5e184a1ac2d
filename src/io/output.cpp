// history.csv and hoop.csv: the time series of a run and the hole measure's curve.
#include "gimp/io/output.hpp"

#include <unistd.h>

#include <cmath>

namespace gimp {

namespace {

const char *const kAxes[] = {"x", "y", "z"};

} // namespace

template <int D> PetscErrorCode Output<D>::open(const OutputResume *resume) {
  PetscCall(prepare(resume, sc_.particleDump, sc_.gridDump));
  if (resume) return frames_.empty() ? PETSC_SUCCESS : writeXdmf();
  if (rank_ == 0) {
    std::fprintf(history_, "step,time,kinetic,strain,external_work,damping,total");
    for (int a = 0; a < D; ++a)
      std::fprintf(history_, ",momentum_%s", kAxes[a]);
    std::fprintf(history_, ",separation,strain_x");
    for (const Probe<D> &p : sc_.probes) {
      for (int a = 0; a < D; ++a)
        std::fprintf(history_, ",%s_u%s", p.name.c_str(), kAxes[a]);
      for (const char *c : stressComponents<D>())
        std::fprintf(history_, ",%s_s%s", p.name.c_str(), c);
    }
    for (size_t q = 0; q < sc_.dbcs.size(); ++q) {
      for (int a = 0; a < D; ++a)
        std::fprintf(history_, ",dbc%zu_f%s", q, kAxes[a]);
      std::fprintf(history_, ",dbc%zu_gap", q);
    }
    if (sc_.mms != Mms::None) std::fprintf(history_, ",mms_linf,mms_rms");
    if constexpr (D == 2)
      for (const cracks::TipMeasure &m : cracks::tipsOf(sc_))
        for (const char *c : {"G_vcct", "GII_vcct", "G_J", "KI_vcct", "KII_vcct", "KI_J", "KII_J",
                              "opening_n", "opening_t"})
          std::fprintf(history_, ",crack%d_tip%d_%s", m.crack, m.end, c);
    if constexpr (D == 2) // with growth, where each tip is
      for (const cracks::TipMeasure &m : cracks::tipsOf(sc_))
        for (const char *c : {"x", "y"})
          if (sc_.growth != Growth::None)
            std::fprintf(history_, ",crack%d_tip%d_%s", m.crack, m.end, c);
    if constexpr (D == 3) // each crack's front: the mean and extremes over its front points
      for (size_t k = 0; k < sc_.cracks.size(); ++k)
        for (const char *q : {"G", "KI", "KII", "KIII"})
          for (const char *w : {"mean", "min", "max"})
            std::fprintf(history_, ",crack%zu_%s_%s", k, q, w);
    if constexpr (D == 3) // with growth, how far each front has advanced
      for (const FrontGrowth &g : sc_.frontGrowth)
        std::fprintf(history_, ",crack%d_advance_mean,crack%d_advance_max", g.crack, g.crack);
    std::fprintf(history_, "\n");
  }
  return flushHistory(0);
}

template <int D> PetscErrorCode Output<D>::writeHistory(const HistoryRow &r) {
  if (rank_ != 0) return flushHistory(0);
  const long rowStart = std::ftell(history_);
  const Energies &e = r.energy;
  std::fprintf(history_, "%lld,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e", static_cast<long long>(r.step),
               r.t, e.kinetic, e.strain, e.externalWork, e.damping, e.total());
  for (int a = 0; a < D; ++a)
    std::fprintf(history_, ",%.12e", e.momentum[a]);
  std::fprintf(history_, ",%.12e,%.12e", r.separation, r.strainX);
  const size_t ns = stressComponents<D>().size();
  for (const ProbeState &p : r.probes) {
    for (int a = 0; a < D; ++a)
      std::fprintf(history_, ",%.12e", p.u[a]);
    for (size_t c = 0; c < ns; ++c)
      std::fprintf(history_, ",%.12e", p.stress[c]);
  }
  for (size_t q = 0; q < r.gaps.size(); ++q) {
    for (int a = 0; a < D; ++a)
      std::fprintf(history_, ",%.12e", r.reactions[D * q + a]);
    std::fprintf(history_, ",%.12e", r.gaps[q]);
  }
  if (sc_.mms != Mms::None) std::fprintf(history_, ",%.12e,%.12e", r.mmsLinf, r.mmsRms);
  for (const cracks::TipMeasure &m : r.tips)
    std::fprintf(history_, ",%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e", m.G_vcct,
                 m.GII_vcct, m.G_J, m.KI_vcct, m.KII_vcct, m.KI_J, m.KII_J, m.opening[0],
                 m.opening[1]);
  for (const cracks::TipMeasure &m : r.tips)
    if (sc_.growth != Growth::None) std::fprintf(history_, ",%.12e,%.12e", m.tip[0], m.tip[1]);
  for (size_t k = 0; D == 3 && k < sc_.cracks.size(); ++k)
    for (const auto value : {&cracks::FrontMeasure::G, &cracks::FrontMeasure::KI,
                             &cracks::FrontMeasure::KII, &cracks::FrontMeasure::KIII}) {
      double sum = 0, lo = INFINITY, hi = -INFINITY;
      int n = 0;
      for (const cracks::FrontMeasure &f : r.front) {
        if (f.crack != static_cast<int>(k) || !(f.R > 0)) continue; // no tube fits: not measured
        sum += f.*value;
        lo = std::min(lo, f.*value);
        hi = std::max(hi, f.*value);
        ++n;
      }
      const double mean = n ? sum / n : NAN;
      std::fprintf(history_, ",%.12e,%.12e,%.12e", mean, n ? lo : NAN, n ? hi : NAN);
    }
  if constexpr (D == 3)
    for (const FrontGrowth &g : sc_.frontGrowth) { // front points' distance from the crack given
      double sum = 0, hi = 0;
      int n = 0;
      for (const cracks::FrontMeasure &f : r.front) {
        if (f.crack != g.crack) continue;
        const double d = cracks::distance(g.start, f.x.data());
        sum += d;
        hi = std::max(hi, d);
        ++n;
      }
      std::fprintf(history_, ",%.12e,%.12e", n ? sum / n : NAN, n ? hi : NAN);
    }
  std::fprintf(history_, "\n");
  return flushHistory(rowStart);
}

template <int D> PetscErrorCode Output<D>::writeHoop(const HoleMeasure &h) {
  FILE *f = nullptr;
  PetscCall(openOnRoot("hoop.csv", &f, true));
  if (rank_ == 0) {
    std::fprintf(f, "angle_deg,r,hoop_over_p,kirsch\n");
    for (const std::vector<double> &r : h.rows)
      std::fprintf(f, "%.6f,%.9e,%.9e,%.9e\n", r[0], r[1], r[2], r[3]);
  }
  PetscCall(closeOnRoot("hoop.csv", f, true));
  PetscCall(openOnRoot("hoop_fit.csv", &f, true));
  if (rank_ == 0) {
    std::fprintf(f, "angle_deg,edge_hoop_over_p,kirsch_edge,particles\n");
    for (const auto &c : h.curve)
      std::fprintf(f, "%.3f,%.9e,%.9e,%d\n", c[0], c[1], c[2], static_cast<int>(c[3]));
  }
  return closeOnRoot("hoop_fit.csv", f, true);
}

#define GIMP_INSTANTIATE(D)                                                                        \
  template PetscErrorCode Output<D>::open(const OutputResume *);                                   \
  template PetscErrorCode Output<D>::writeHistory(const HistoryRow &);                             \
  template PetscErrorCode Output<D>::writeHoop(const HoleMeasure &);
GIMP_INSTANTIATE(2)
GIMP_INSTANTIATE(3)
#undef GIMP_INSTANTIATE

} // namespace gimp
