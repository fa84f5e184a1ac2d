// summary.json (docs/output.md): strict JSON, written whole or not at all.
#include "gimp/io/json.hpp"
#include "gimp/io/output.hpp"

#include <cmath>

namespace gimp {

std::string jsonNumber(double v) {
  if (!std::isfinite(v)) return "null";
  char b[64];
  std::snprintf(b, sizeof(b), "%.12e", v);
  return b;
}

namespace {

/// Length of the valid UTF-8 sequence starting at s[i], 0 when it is not one.
size_t utf8Length(const std::string &s, size_t i) {
  const unsigned char c = static_cast<unsigned char>(s[i]);
  const size_t n = c < 0x80 ? 1 : (c >> 5) == 6 ? 2 : (c >> 4) == 14 ? 3 : (c >> 3) == 30 ? 4 : 0;
  if (n == 0 || i + n > s.size()) return 0;
  for (size_t k = 1; k < n; ++k)
    if ((static_cast<unsigned char>(s[i + k]) >> 6) != 2) return 0;
  return n;
}

} // namespace

std::string jsonString(const std::string &s) {
  std::string r = "\"";
  for (size_t i = 0; i < s.size();) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    const size_t n = utf8Length(s, i);
    if (c == '"' || c == '\\') {
      r += '\\';
      r += static_cast<char>(c);
    } else if (c < 0x20) {
      char b[8];
      std::snprintf(b, sizeof(b), "\\u%04x", c);
      r += b;
    } else if (n == 0) {
      r += "\\ufffd";
    } else {
      r += s.substr(i, n);
    }
    i += n ? n : 1;
  }
  return r + "\"";
}

namespace {

const auto num = jsonNumber;

/// "[a, b, ...]": n numbers of v.
std::string numbers(const double *v, int n) {
  std::string r = "[";
  for (int i = 0; i < n; ++i)
    r += (i ? ", " : "") + num(v[i]);
  return r + "]";
}

/// The 3D cracks: per crack the radius asked for and its front points, each with its position, G
/// and K (null where no tube fits), and the domain (R, L) its integrals took, and whether R was
/// clipped to the point's clearance.
/// The 3D cracks' fronts, and with growth each crack's increments (one per front point advanced).
void writeFronts(FILE *f, const std::vector<cracks::FrontMeasure> &front,
                 const std::vector<cracks::GrowthRecord> *growth) {
  const auto close = [&](int crack) {
    std::fprintf(f, "]");
    if (growth) {
      std::fprintf(f, ", \"growth\": [");
      int n = 0;
      for (const cracks::GrowthRecord &g : *growth)
        if (g.crack == crack)
          std::fprintf(f,
                       "%s{\"t\": %s, \"point\": %d, \"x\": %s, \"G\": %s, \"KI\": %s, "
                       "\"KII\": %s, \"KIII\": %s, \"kink\": %s}",
                       n++ ? ", " : "", num(g.t).c_str(), g.end, numbers(g.x, 3).c_str(),
                       num(g.G).c_str(), num(g.KI).c_str(), num(g.KII).c_str(), num(g.KIII).c_str(),
                       num(g.kink).c_str());
      std::fprintf(f, "]");
    }
    std::fprintf(f, "}");
  };
  std::fprintf(f, ",\n  \"cracks\": [");
  int crack = -1;
  for (const cracks::FrontMeasure &m : front) {
    const bool next = m.crack != crack;
    if (next && crack >= 0) {
      close(crack);
      std::fprintf(f, ",");
    }
    if (next)
      std::fprintf(f, "\n    {\"crack\": %d, \"j_radius\": %s, \"front\": [", m.crack,
                   num(m.asked).c_str());
    std::fprintf(f,
                 "%s\n      {\"x\": %s, \"edge\": %d, \"G\": %s, \"KI\": %s, \"KII\": %s, "
                 "\"KIII\": %s, \"R\": %s, \"L\": %s, \"clipped\": %s, \"images\": %d}",
                 next ? "" : ",", numbers(m.x.data(), 3).c_str(), m.edge, num(m.G).c_str(),
                 num(m.KI).c_str(), num(m.KII).c_str(), num(m.KIII).c_str(), num(m.R).c_str(),
                 num(m.L).c_str(), m.clipped ? "true" : "false", m.images);
    crack = m.crack;
  }
  close(crack);
  std::fprintf(f, "]");
}

} // namespace

template <int D> PetscErrorCode Output<D>::writeSummary(const SummaryReport &r) {
  FILE *f = nullptr;
  PetscCall(openOnRoot("summary.json", &f, true));
  if (rank_ == 0) {
    summaryRun(f, r);
    summaryState(f, r);
    summaryMeasures(f, r);
    std::fprintf(f, "\n}\n");
  }
  return closeOnRoot("summary.json", f, true);
}

template <int D> void Output<D>::summaryRun(FILE *f, const SummaryReport &r) const {
  std::fprintf(f,
               "{\n  \"scene\": %s,\n  \"version\": %s,\n  \"dim\": %d,\n  \"status\": %s,\n"
               "  \"failure\": %s,\n",
               jsonString(sc_.name).c_str(), jsonString(GIMP_VERSION).c_str(), D,
               jsonString(r.status).c_str(), jsonString(r.failure).c_str());
  // The scheme the run used, defaults included (the default tracking depends on -gimp_multirate).
  std::fprintf(f,
               "  \"method\": {\"update\": \"%s\", \"transfer\": \"%s\", \"tracking\": \"%s\", "
               "\"multirate\": %s},\n",
               kUpdateNames[static_cast<int>(sc_.update)],
               kTransferNames[static_cast<int>(sc_.transfer)],
               kTrackingNames[static_cast<int>(sc_.tracking)], sc_.multirate ? "true" : "false");
  std::fprintf(f,
               "  \"ranks\": %d,\n  \"steps\": %lld,\n  \"time\": %s,\n  \"dt\": %s,\n"
               "  \"wall_seconds\": %s,\n  \"setup_seconds\": %s,\n  \"cpu_seconds\": %s,\n"
               "  \"particles\": %lld,\n",
               r.ranks, static_cast<long long>(r.steps), num(r.t).c_str(), num(r.dt).c_str(),
               num(r.seconds.wall).c_str(), num(r.seconds.setup).c_str(),
               num(r.seconds.cpu).c_str(), static_cast<long long>(r.particles));
  std::fprintf(f, "  \"particle_steps_per_second\": %s,\n",
               num(static_cast<double>(r.particles) * static_cast<double>(r.steps) / r.seconds.wall)
                   .c_str());
  std::fprintf(f, "  \"dt_critical\": %s,\n", num(r.dtCritical).c_str());
  std::fprintf(f, "  \"levels\": [");
  for (size_t k = 0; k < grid_.levels.size(); ++k) {
    // One level per line (bench/run_bench.sh reads level 0's line).
    const Level<D> &L = grid_.levels[k];
    std::string nodes = "[";
    for (int a = 0; a < D; ++a)
      nodes += (a ? ", " : "") + std::to_string(static_cast<long long>(L.n[a]));
    nodes += "]";
    std::fprintf(f,
                 "%s\n    {\"h\": %s, \"ratio\": %d, \"box\": %s, \"nodes\": %s, "
                 "\"active_nodes\": %lld}",
                 k ? "," : "", num(L.h).c_str(), k ? sc_.levels[k].ratio : 1,
                 numbers(L.box.data(), 2 * D).c_str(), nodes.c_str(),
                 static_cast<long long>(grid_.activeNodes(static_cast<int>(k))));
  }
  std::fprintf(f, "],\n");
}

template <int D> void Output<D>::summaryState(FILE *f, const SummaryReport &r) const {
  const Energies &e = r.energy;
  std::fprintf(f,
               "  \"energy\": {\"kinetic\": %s, \"strain\": %s, \"external_work\": %s, "
               "\"damping\": %s, \"total\": %s},\n",
               num(e.kinetic).c_str(), num(e.strain).c_str(), num(e.externalWork).c_str(),
               num(e.damping).c_str(), num(e.total()).c_str());
  std::fprintf(f, "  \"momentum\": %s,\n", numbers(e.momentum, D).c_str());
  std::fprintf(f, "  \"reactions\": {");
  for (size_t q = 0; q < sc_.dbcs.size(); ++q)
    std::fprintf(f, "%s\"dbc%zu\": %s", q ? ", " : "", q, numbers(&r.reactions[D * q], D).c_str());
  std::fprintf(f, "},\n  \"penalty\": %s,\n", num(r.penalty).c_str());
  if (!sc_.dbcs.empty()) {
    std::fprintf(f, "  \"constraint_violation\": {");
    for (size_t q = 0; q < sc_.dbcs.size(); ++q)
      std::fprintf(f, "%s\"dbc%zu\": {\"final\": %s, \"max\": %s}", q ? ", " : "", q,
                   num(r.gaps[q]).c_str(), num(r.maxGaps[q]).c_str());
    std::fprintf(f, "},\n");
  }
  std::fprintf(f, "  \"probes\": {");
  const int ns = static_cast<int>(stressComponents<D>().size());
  for (size_t q = 0; q < r.probes.size(); ++q) {
    const ProbeState &p = r.probes[q];
    std::fprintf(f, "%s\n    %s: {\"id\": %lld, \"x0\": %s, \"u\": %s, \"stress\": %s}",
                 q ? "," : "", jsonString(sc_.probes[q].name).c_str(), static_cast<long long>(p.id),
                 numbers(p.X0, D).c_str(), numbers(p.u, D).c_str(), numbers(p.stress, ns).c_str());
  }
}

template <int D> void Output<D>::summaryMeasures(FILE *f, const SummaryReport &r) const {
  const RunMeasures &m = r.measures;
  std::fprintf(f, "%s},\n  \"measures\": {", r.probes.empty() ? "" : "\n  ");
  std::fprintf(f, "\"particles_migrated\": %lld", static_cast<long long>(m.migrated));
  // The separation measure.
  std::fprintf(f, ", \"separation_strain\": %s", num(m.separationStrain).c_str());
  std::fprintf(f, ", \"max_strain\": %s, \"max_separation\": %s", num(m.maxStrain).c_str(),
               num(m.maxSeparation).c_str());
  if (r.hole) {
    // kt_edge: the same edge value as kt, under the name earlier versions gave it.
    std::fprintf(f, ", \"kt\": %s, \"kt_edge\": %s, \"kt_particle\": %s", num(r.hole->kt).c_str(),
                 num(r.hole->kt).c_str(), num(r.hole->ktParticle).c_str());
    std::fprintf(f, ", \"hoop_max_error\": %s", num(r.hole->maxError).c_str());
    for (size_t a = 0; a < r.hole->hoopByAngle.size(); ++a)
      std::fprintf(f, ", \"hoop_%zu\": %s", 15 * a, num(r.hole->hoopByAngle[a]).c_str());
  }
  if (sc_.mms != Mms::None)
    std::fprintf(f, ", \"mms_linf\": %s, \"mms_rms\": %s", num(m.mmsLinf).c_str(),
                 num(m.mmsRms).c_str());
  if (sc_.follows()) { // the moves of the level boxes that follow a point
    std::fprintf(f, ", \"regrids\": [");
    const auto sums = [&](const Conserved &c) {
      return "{\"mass\": " + num(c.mass) + ", \"momentum\": " + numbers(c.momentum, D) +
             ", \"angular_momentum\": " + numbers(c.angular, D == 2 ? 3 : D) +
             ", \"energy\": " + num(c.energy) + "}";
    };
    for (size_t q = 0; q < m.regrids.size(); ++q) {
      const RegridRecord &g = m.regrids[q];
      std::fprintf(f,
                   "%s{\"t\": %s, \"step\": %lld, \"level\": %d, \"box\": %s, "
                   "\"previous\": %s, \"particles_added\": %lld, \"before\": %s, "
                   "\"after\": %s}",
                   q ? ", " : "", num(g.t).c_str(), static_cast<long long>(g.step), g.level,
                   numbers(g.box.data(), 2 * D).c_str(), numbers(g.previous.data(), 2 * D).c_str(),
                   static_cast<long long>(g.added), sums(g.before).c_str(), sums(g.after).c_str());
    }
    std::fprintf(f, "]");
  }
  std::fprintf(f, "}");
  if (!r.front.empty()) writeFronts(f, r.front, sc_.growth != Growth::None ? &m.growth : nullptr);
  if (r.tips.empty()) return;
  std::fprintf(f, ",\n  \"cracks\": [");
  for (size_t q = 0; q < r.tips.size(); ++q) {
    const cracks::TipMeasure &t = r.tips[q];
    std::fprintf(f,
                 "%s\n    {\"crack\": %d, \"end\": %d, \"tip\": [%s, %s], \"G_vcct\": %s, "
                 "\"GII_vcct\": %s, \"G_J\": %s, \"KI_vcct\": %s, \"KII_vcct\": %s, \"KI_J\": %s, "
                 "\"KII_J\": %s, \"h\": %s, \"opening\": [%s, %s], \"j_radius\": %s, "
                 "\"j_domain_clipped\": %s",
                 q ? "," : "", t.crack, t.end, num(t.tip[0]).c_str(), num(t.tip[1]).c_str(),
                 num(t.G_vcct).c_str(), num(t.GII_vcct).c_str(), num(t.G_J).c_str(),
                 num(t.KI_vcct).c_str(), num(t.KII_vcct).c_str(), num(t.KI_J).c_str(),
                 num(t.KII_J).c_str(), num(t.h).c_str(), num(t.opening[0]).c_str(),
                 num(t.opening[1]).c_str(), num(t.jRadius > 0 ? t.jRadius : std::nan("")).c_str(),
                 t.jClipped ? "true" : "false");
    if (sc_.growth != Growth::None) { // the tip's increments, in order
      std::fprintf(f, ", \"growth\": [");
      int n = 0;
      for (const cracks::GrowthRecord &g : m.growth)
        if (g.crack == t.crack && g.end == t.end)
          std::fprintf(f,
                       "%s{\"t\": %s, \"tip\": %d, \"x\": [%s, %s], \"G\": %s, \"KI\": %s, "
                       "\"KII\": %s, \"kink\": %s}",
                       n++ ? ", " : "", num(g.t).c_str(), g.end, num(g.x[0]).c_str(),
                       num(g.x[1]).c_str(), num(g.G).c_str(), num(g.KI).c_str(), num(g.KII).c_str(),
                       num(g.kink).c_str());
      std::fprintf(f, "]");
    }
    std::fprintf(f, "}");
  }
  std::fprintf(f, "]");
}

template PetscErrorCode Output<2>::writeSummary(const SummaryReport &);
template PetscErrorCode Output<3>::writeSummary(const SummaryReport &);

} // namespace gimp
