// The run state a checkpoint keeps beyond particles and scalars (checkpoint_state.hpp).
#include "checkpoint_state.hpp"

namespace gimp {

template <int D>
void growthState(const RunState<D> &s, std::vector<double> &cracks, std::vector<double> &growth) {
  if constexpr (D == 2) {
    for (const Crack &c : s.sc.cracks) {
      cracks.insert(cracks.end(),
                    {static_cast<double>(c.points.size()), static_cast<double>(c.grown[0]),
                     static_cast<double>(c.grown[1])});
      for (const auto &p : c.points)
        cracks.insert(cracks.end(), p.begin(), p.end());
    }
    for (const TipGrowth &g : s.sc.tipGrowth)
      cracks.push_back(g.stopped ? 1.0 : 0.0);
    for (const cracks::GrowthRecord &r : s.measures.growth)
      growth.insert(growth.end(), {r.t, static_cast<double>(r.crack), static_cast<double>(r.end),
                                   r.x[0], r.x[1], r.G, r.KI, r.KII, r.kink});
  } else {
    const auto put = [&](const CrackSurface &c) {
      cracks.push_back(static_cast<double>(c.points.size()));
      for (const auto &p : c.points)
        cracks.insert(cracks.end(), p.begin(), p.end());
      for (const char f : c.front)
        cracks.push_back(f);
    };
    for (const CrackSurface &c : s.sc.cracks)
      put(c);
    for (const FrontGrowth &g : s.sc.frontGrowth)
      cracks.push_back(g.stopped ? 1.0 : 0.0);
    // (then the polygons before the advances still opening: none without a release time)
    for (const FrontGrowth &g : s.sc.frontGrowth) {
      cracks.push_back(static_cast<double>(g.opening.size()));
      for (const auto &[t0, before] : g.opening) {
        cracks.push_back(t0);
        put(before);
      }
    }
    for (const cracks::GrowthRecord &r : s.measures.growth)
      growth.insert(growth.end(), {r.t, static_cast<double>(r.crack), static_cast<double>(r.end),
                                   r.x[0], r.x[1], r.x[2], r.G, r.KI, r.KII, r.KIII, r.kink});
  }
}

template <int D>
void restoreGrowth(RunState<D> &s, const std::vector<double> &cracks,
                   const std::vector<double> &growth) {
  if constexpr (D == 2) {
    size_t q = 0;
    for (Crack &c : s.sc.cracks) {
      const size_t n = static_cast<size_t>(cracks.at(q));
      c.grown[0] = static_cast<int>(cracks.at(q + 1));
      c.grown[1] = static_cast<int>(cracks.at(q + 2));
      q += 3;
      c.points.resize(n);
      for (auto &p : c.points) {
        p = {cracks.at(q), cracks.at(q + 1)};
        q += 2;
      }
    }
    for (TipGrowth &g : s.sc.tipGrowth)
      g.stopped = cracks.at(q++) != 0;
    s.measures.growth.clear();
    for (size_t k = 0; k + 8 < growth.size(); k += 9) {
      cracks::GrowthRecord r;
      r.t = growth[k];
      r.crack = static_cast<int>(growth[k + 1]);
      r.end = static_cast<int>(growth[k + 2]);
      r.x[0] = growth[k + 3];
      r.x[1] = growth[k + 4];
      r.G = growth[k + 5];
      r.KI = growth[k + 6];
      r.KII = growth[k + 7];
      r.kink = growth[k + 8];
      s.measures.growth.push_back(r);
    }
  } else {
    size_t q = 0;
    const auto get = [&](CrackSurface &c, const double *normal) {
      const size_t n = static_cast<size_t>(cracks.at(q++));
      std::vector<std::array<double, 3>> pts(n);
      for (auto &p : pts) {
        p = {cracks.at(q), cracks.at(q + 1), cracks.at(q + 2)};
        q += 3;
      }
      std::vector<char> front(n);
      for (char &f : front)
        f = static_cast<char>(cracks.at(q++) != 0);
      c = cracks::makeSurface(pts, normal);
      c.front = front;
    };
    for (CrackSurface &c : s.sc.cracks)
      get(c, c.normal.data());
    for (FrontGrowth &g : s.sc.frontGrowth)
      g.stopped = cracks.at(q++) != 0;
    for (FrontGrowth &g : s.sc.frontGrowth) { // (absent from checkpoints that kept none)
      g.opening.resize(q < cracks.size() ? static_cast<size_t>(cracks.at(q++)) : 0);
      for (auto &[t0, before] : g.opening) {
        t0 = cracks.at(q++);
        get(before, s.sc.cracks[static_cast<size_t>(g.crack)].normal.data());
      }
    }
    s.measures.growth.clear();
    for (size_t k = 0; k + 10 < growth.size(); k += 11) {
      cracks::GrowthRecord r;
      r.t = growth[k];
      r.crack = static_cast<int>(growth[k + 1]);
      r.end = static_cast<int>(growth[k + 2]);
      for (int a = 0; a < 3; ++a)
        r.x[a] = growth[k + 3 + a];
      r.G = growth[k + 6];
      r.KI = growth[k + 7];
      r.KII = growth[k + 8];
      r.KIII = growth[k + 9];
      r.kink = growth[k + 10];
      s.measures.growth.push_back(r);
    }
  }
}

namespace {

void putSums(const Conserved &c, std::vector<double> &a) {
  a.push_back(c.mass);
  a.insert(a.end(), c.momentum, c.momentum + 3);
  a.insert(a.end(), c.angular, c.angular + 3);
  a.push_back(c.energy);
}

Conserved getSums(const std::vector<double> &a, size_t &q) {
  Conserved c;
  c.mass = a.at(q++);
  for (double &x : c.momentum)
    x = a.at(q++);
  for (double &x : c.angular)
    x = a.at(q++);
  c.energy = a.at(q++);
  return c;
}

} // namespace

template <int D> std::vector<double> followState(const RunState<D> &s) {
  const SplitIds &ids = s.splitIds;
  std::vector<double> a = {static_cast<double>(ids.seeded), static_cast<double>(ids.used.size())};
  for (const std::vector<PetscInt64> *v : {&ids.seededTop, &ids.used})
    for (PetscInt64 x : *v)
      a.push_back(static_cast<double>(x));
  for (const RegridRecord &r : s.measures.regrids) {
    a.insert(a.end(), {r.t, static_cast<double>(r.step), static_cast<double>(r.level)});
    a.insert(a.end(), r.box.begin(), r.box.end());
    a.insert(a.end(), r.previous.begin(), r.previous.end());
    a.push_back(static_cast<double>(r.added));
    putSums(r.before, a);
    putSums(r.after, a);
  }
  return a;
}

template <int D> bool restoreFollow(RunState<D> &s, const std::vector<double> &a) {
  if (a.size() < 2 || a[0] <= 0 || a[0] != static_cast<double>(s.nParticles)) return false;
  const auto nb = static_cast<size_t>(a[1]);
  if (a.size() < 2 + 2 * nb || (a.size() - 2 - 2 * nb) % 32 != 0) return false;
  SplitIds ids;
  ids.seeded = static_cast<PetscInt64>(a[0]);
  for (size_t b = 0; b < nb; ++b) {
    ids.seededTop.push_back(static_cast<PetscInt64>(a[2 + b]));
    ids.used.push_back(static_cast<PetscInt64>(a[2 + nb + b]));
  }
  std::vector<RegridRecord> moves;
  for (size_t q = 2 + 2 * nb; q < a.size();) {
    RegridRecord r;
    r.t = a[q];
    r.step = static_cast<PetscInt64>(a[q + 1]);
    r.level = static_cast<int>(a[q + 2]);
    std::copy(a.begin() + static_cast<std::ptrdiff_t>(q + 3),
              a.begin() + static_cast<std::ptrdiff_t>(q + 9), r.box.begin());
    std::copy(a.begin() + static_cast<std::ptrdiff_t>(q + 9),
              a.begin() + static_cast<std::ptrdiff_t>(q + 15), r.previous.begin());
    r.added = static_cast<PetscInt64>(a[q + 15]);
    q += 16;
    r.before = getSums(a, q);
    r.after = getSums(a, q);
    moves.push_back(r);
  }
  s.splitIds = ids;
  s.measures.regrids = moves;
  return true;
}

#define GIMP_INSTANTIATE(D)                                                                        \
  template void growthState<D>(const RunState<D> &, std::vector<double> &, std::vector<double> &); \
  template void restoreGrowth<D>(RunState<D> &, const std::vector<double> &,                       \
                                 const std::vector<double> &);                                     \
  template std::vector<double> followState<D>(const RunState<D> &);                                \
  template bool restoreFollow<D>(RunState<D> &, const std::vector<double> &);
GIMP_INSTANTIATE(2)
GIMP_INSTANTIATE(3)
#undef GIMP_INSTANTIATE

} // namespace gimp
