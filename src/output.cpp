#include "gimp/output.hpp"

#include "gimp/simulation.hpp"

#include <petscviewerhdf5.h>

#include <cmath>
#include <filesystem>
#include <vector>

namespace gimp {

namespace {

const char *const kParticleFields[] = {"x", "X0", "v", "stress", "l", "V", "m", "corners"};
const int kParticleFieldSizes[] = {2, 2, 2, 4, 2, 1, 1, 8};
constexpr size_t kAlwaysWritten = 7; // "corners" only with corner tracking

size_t particleFieldCount(const Scene &sc) {
  return sc.tracking == Tracking::Corners ? kAlwaysWritten + 1 : kAlwaysWritten;
}

std::string groupName(PetscInt step) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "step_%08lld", static_cast<long long>(step));
  return buf;
}

} // namespace

Output::~Output() {
  if (history_) std::fclose(history_);
}

PetscErrorCode Output::open() {
  dir_ = sim_.sc_.outputDir;
  if (sim_.rank_ == 0) {
    std::error_code ec;
    std::filesystem::create_directories(dir_, ec);
    if (ec)
      throw InputError("option -gimp_output_dir " + dir_ + ": cannot create it (" + ec.message() +
                       ")");
    history_ = std::fopen((dir_ + "/history.csv").c_str(), "w");
    if (!history_)
      throw InputError("option -gimp_output_dir " + dir_ + ": cannot write history.csv there");
    std::fprintf(history_,
                 "step,time,kinetic,strain,external_work,damping,total,momentum_x,momentum_y,"
                 "separation,strain_x");
    for (const Probe &p : sim_.sc_.probes)
      std::fprintf(history_, ",%s_ux,%s_uy,%s_sxx,%s_syy,%s_sxy,%s_szz", p.name.c_str(),
                   p.name.c_str(), p.name.c_str(), p.name.c_str(), p.name.c_str(), p.name.c_str());
    for (size_t q = 0; q < sim_.sc_.dbcs.size(); ++q)
      std::fprintf(history_, ",dbc%zu_fx,dbc%zu_fy,dbc%zu_gap", q, q, q);
    if (sim_.sc_.mms != Mms::None) std::fprintf(history_, ",mms_linf,mms_rms");
    std::fprintf(history_, "\n");
    std::fflush(history_);
  }
  PetscCallMPI(MPI_Barrier(sim_.comm_));
  // Remove fields of an earlier run in the same directory.
  if (sim_.rank_ == 0) {
    std::error_code ec;
    std::filesystem::remove(dir_ + "/fields.h5", ec);
    std::filesystem::remove(dir_ + "/particles.xmf", ec);
    std::filesystem::remove(dir_ + "/grid.xmf", ec);
  }
  PetscCallMPI(MPI_Barrier(sim_.comm_));
  return PETSC_SUCCESS;
}

PetscErrorCode Output::writeHistory(PetscInt step, double t) {
  Energies e;
  std::vector<ProbeState> probes;
  double linf = 0, rms = 0;
  PetscCall(sim_.energies(e));
  PetscCall(sim_.probes(probes));
  PetscCall(sim_.mmsErrors(t, linf, rms));
  std::vector<double> reactions, gaps;
  PetscCall(sim_.reactionForces(reactions, gaps));
  double gap = 0, strain = 0;
  PetscCall(sim_.separation(t, step, gap, strain));
  if (sim_.rank_ != 0) return PETSC_SUCCESS;
  std::fprintf(history_, "%lld,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e",
               static_cast<long long>(step), t, e.kinetic, e.strain, e.externalWork, e.damping,
               e.total(), e.momentum[0], e.momentum[1]);
  std::fprintf(history_, ",%.12e,%.12e", gap, strain);
  for (const ProbeState &p : probes)
    std::fprintf(history_, ",%.12e,%.12e,%.12e,%.12e,%.12e,%.12e", p.u[0], p.u[1], p.stress[0],
                 p.stress[1], p.stress[2], p.stress[3]);
  for (size_t q = 0; q < gaps.size(); ++q)
    std::fprintf(history_, ",%.12e,%.12e,%.12e", reactions[2 * q], reactions[2 * q + 1], gaps[q]);
  if (sim_.sc_.mms != Mms::None) std::fprintf(history_, ",%.12e,%.12e", linf, rms);
  std::fprintf(history_, "\n");
  std::fflush(history_);
  return PETSC_SUCCESS;
}

PetscErrorCode Output::writeFields(PetscInt step, double t) {
  PetscViewer v;
  const std::string file = dir_ + "/fields.h5";
  PetscCall(PetscViewerHDF5Open(sim_.comm_, file.c_str(),
                                frames_.empty() ? FILE_MODE_WRITE : FILE_MODE_APPEND, &v));
  const std::string g = groupName(step);
  PetscCall(PetscViewerHDF5PushGroup(v, ("/particles/" + g).c_str()));
  PetscInt nloc = 0;
  PetscCall(DMSwarmGetLocalSize(sim_.sw_, &nloc));
  for (size_t k = 0; k < particleFieldCount(sim_.sc_); ++k) {
    // A plain MPI Vec over the field array: written as an (N, components) dataset.
    const char *name = kParticleFields[k];
    const PetscInt bs = kParticleFieldSizes[k];
    PetscScalar *data = nullptr;
    Vec f;
    PetscCall(DMSwarmGetField(sim_.sw_, name, nullptr, nullptr, reinterpret_cast<void **>(&data)));
    PetscCall(VecCreateMPIWithArray(sim_.comm_, bs, bs * nloc, PETSC_DECIDE, data, &f));
    PetscCall(PetscObjectSetName(reinterpret_cast<PetscObject>(f), name));
    PetscCall(VecView(f, v));
    PetscCall(VecDestroy(&f));
    PetscCall(
        DMSwarmRestoreField(sim_.sw_, name, nullptr, nullptr, reinterpret_cast<void **>(&data)));
  }
  PetscCall(PetscViewerHDF5WriteAttribute(v, nullptr, "time", PETSC_DOUBLE, &t));
  PetscCall(PetscViewerHDF5PopGroup(v));
  // Grid: each level's velocity and mass as (N, M[, 2]) datasets.
  const Grid &grid = sim_.grid_;
  const int K = static_cast<int>(grid.levels.size());
  std::vector<Vec> vel(K), mass(K);
  PetscCall(DMCompositeGetAccessArray(grid.dm, sim_.vel_, K, nullptr, vel.data()));
  PetscCall(DMCompositeGetAccessArray(grid.dm, sim_.mass_, K, nullptr, mass.data()));
  for (int k = 0; k < K; ++k) {
    const Level &L = grid.levels[k];
    Vec m1;
    PetscCall(PetscViewerHDF5PushGroup(v, ("/grid/" + g + "/level_" + std::to_string(k)).c_str()));
    PetscCall(PetscObjectSetName(reinterpret_cast<PetscObject>(vel[k]), "velocity"));
    PetscCall(VecView(vel[k], v));
    PetscCall(DMGetGlobalVector(L.da1, &m1));
    PetscCall(VecStrideGather(mass[k], 0, m1, INSERT_VALUES));
    PetscCall(PetscObjectSetName(reinterpret_cast<PetscObject>(m1), "mass"));
    PetscCall(VecView(m1, v));
    PetscCall(DMRestoreGlobalVector(L.da1, &m1));
    PetscCall(PetscViewerHDF5PopGroup(v));
  }
  PetscCall(DMCompositeRestoreAccessArray(grid.dm, sim_.mass_, K, nullptr, mass.data()));
  PetscCall(DMCompositeRestoreAccessArray(grid.dm, sim_.vel_, K, nullptr, vel.data()));
  PetscCall(PetscViewerDestroy(&v));
  PetscInt64 n = 0;
  PetscCall(sim_.particleCount(n));
  frames_.push_back({step, t, static_cast<long long>(n)});
  PetscCall(writeXdmf());
  return PETSC_SUCCESS;
}

PetscErrorCode Output::writeXdmf() const {
  if (sim_.rank_ != 0) return PETSC_SUCCESS;
  const Grid &grid = sim_.grid_;
  FILE *fp = std::fopen((dir_ + "/particles.xmf").c_str(), "w");
  FILE *fg = std::fopen((dir_ + "/grid.xmf").c_str(), "w");
  if (!fp || !fg) {
    if (fp) std::fclose(fp);
    if (fg) std::fclose(fg);
    throw InputError("option -gimp_output_dir " + dir_ + ": cannot write the XDMF files there");
  }
  const char *head = "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n"
                     "<Grid Name=\"%s\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  std::fprintf(fp, head, "particles");
  std::fprintf(fg, head, "grid");
  for (const Frame &fr : frames_) {
    const std::string g = groupName(fr.step);
    std::fprintf(fp,
                 " <Grid Name=\"%s\" GridType=\"Uniform\">\n  <Time Value=\"%.12e\"/>\n"
                 "  <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"%lld\"/>\n"
                 "  <Geometry GeometryType=\"XY\"><DataItem Dimensions=\"%lld 2\" "
                 "NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">fields.h5:/particles/%s/x"
                 "</DataItem></Geometry>\n",
                 g.c_str(), fr.t, fr.particles, fr.particles, g.c_str());
    for (size_t k = 1; k < particleFieldCount(sim_.sc_); ++k) {
      const int nc = kParticleFieldSizes[k];
      std::fprintf(fp,
                   "  <Attribute Name=\"%s\" AttributeType=\"%s\" Center=\"Node\"><DataItem "
                   "Dimensions=\"%lld%s\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">"
                   "fields.h5:/particles/%s/%s</DataItem></Attribute>\n",
                   kParticleFields[k], nc == 1 ? "Scalar" : "Matrix", fr.particles,
                   nc == 1 ? ""
                           : (nc == 2   ? " 2"
                              : nc == 4 ? " 4"
                                        : " 8"),
                   g.c_str(), kParticleFields[k]);
    }
    std::fprintf(fp, " </Grid>\n");
    std::fprintf(fg,
                 " <Grid Name=\"%s\" GridType=\"Collection\" CollectionType=\"Spatial\">\n"
                 "  <Time Value=\"%.12e\"/>\n",
                 g.c_str(), fr.t);
    for (size_t k = 0; k < grid.levels.size(); ++k) {
      const Level &L = grid.levels[k];
      const long long N = L.N, M = L.M;
      const std::string ref = "fields.h5:/grid/" + g + "/level_" + std::to_string(k);
      std::fprintf(fg,
                   "  <Grid Name=\"level_%zu\" GridType=\"Uniform\">\n"
                   "   <Topology TopologyType=\"2DCoRectMesh\" Dimensions=\"%lld %lld\"/>\n"
                   "   <Geometry GeometryType=\"ORIGIN_DXDY\">\n"
                   "    <DataItem Dimensions=\"2\" NumberType=\"Float\" Format=\"XML\">%.17g %.17g"
                   "</DataItem>\n"
                   "    <DataItem Dimensions=\"2\" NumberType=\"Float\" Format=\"XML\">%.17g %.17g"
                   "</DataItem>\n   </Geometry>\n"
                   "   <Attribute Name=\"mass\" AttributeType=\"Scalar\" Center=\"Node\"><DataItem "
                   "Dimensions=\"%lld %lld\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">"
                   "%s/mass</DataItem></Attribute>\n"
                   "   <Attribute Name=\"velocity\" AttributeType=\"Matrix\" Center=\"Node\">"
                   "<DataItem Dimensions=\"%lld %lld 2\" NumberType=\"Float\" Precision=\"8\" "
                   "Format=\"HDF\">%s/velocity</DataItem></Attribute>\n  </Grid>\n",
                   k, N, M, L.box[1], L.box[0], L.h, L.h, N, M, ref.c_str(), N, M, ref.c_str());
    }
    std::fprintf(fg, " </Grid>\n");
  }
  const char *tail = "</Grid>\n</Domain>\n</Xdmf>\n";
  std::fputs(tail, fp);
  std::fputs(tail, fg);
  std::fclose(fp);
  std::fclose(fg);
  return PETSC_SUCCESS;
}

PetscErrorCode Output::writeSummary(PetscInt steps, double t, double wall) {
  Energies e;
  std::vector<ProbeState> probes;
  PetscInt64 n = 0;
  PetscReal dt = 0;
  PetscCall(sim_.energies(e));
  PetscCall(sim_.probes(probes));
  PetscCall(sim_.particleCount(n));
  PetscCall(TSGetTimeStep(sim_.ts_, &dt));
  std::vector<double> reactions, gaps;
  PetscCall(sim_.reactionForces(reactions, gaps));
  double kt = 0, ktEdge = 0;
  if (sim_.sc_.holeMeasure) PetscCall(sim_.holeMeasure(dir_, kt, ktEdge));
  if (sim_.rank_ != 0) return PETSC_SUCCESS;
  const Scene &sc = sim_.sc_;
  const Grid &g = sim_.grid_;
  FILE *f = std::fopen((dir_ + "/summary.json").c_str(), "w");
  if (!f) throw InputError("option -gimp_output_dir " + dir_ + ": cannot write summary.json");
  std::fprintf(f, "{\n  \"scene\": \"%s\",\n  \"version\": \"%s\",\n  \"status\": \"%s\",\n",
               sc.name.c_str(), GIMP_VERSION,
               sim_.failed_   ? "unstable"
               : sim_.atRest_ ? "at_rest"
                              : "completed");
  std::fprintf(f,
               "  \"ranks\": %d,\n  \"steps\": %lld,\n  \"time\": %.12e,\n  \"dt\": %.12e,\n"
               "  \"wall_seconds\": %.6f,\n  \"particles\": %lld,\n",
               sim_.size_, static_cast<long long>(steps), t, dt, wall, static_cast<long long>(n));
  std::fprintf(f, "  \"levels\": [");
  for (size_t k = 0; k < g.levels.size(); ++k) {
    const Level &L = g.levels[k];
    std::fprintf(f,
                 "%s\n    {\"h\": %.12e, \"ratio\": %d, \"box\": [%.12e, %.12e, %.12e, %.12e], "
                 "\"nodes\": [%lld, %lld], \"active_nodes\": %lld}",
                 k ? "," : "", L.h, k ? sc.levels[k].ratio : 1, L.box[0], L.box[1], L.box[2],
                 L.box[3], static_cast<long long>(L.M), static_cast<long long>(L.N),
                 static_cast<long long>(g.activeNodes(static_cast<int>(k))));
  }
  std::fprintf(f, "],\n");
  std::fprintf(f,
               "  \"energy\": {\"kinetic\": %.12e, \"strain\": %.12e, \"external_work\": %.12e, "
               "\"damping\": %.12e},\n",
               e.kinetic, e.strain, e.externalWork, e.damping);
  std::fprintf(f, "  \"momentum\": [%.12e, %.12e],\n", e.momentum[0], e.momentum[1]);
  std::fprintf(f, "  \"reactions\": {");
  for (size_t q = 0; q < sc.dbcs.size(); ++q)
    std::fprintf(f, "%s\"dbc%zu\": [%.12e, %.12e]", q ? ", " : "", q, reactions[2 * q],
                 reactions[2 * q + 1]);
  std::fprintf(f, "},\n");
  if (!sc.dbcs.empty()) {
    std::fprintf(f, "  \"penalty\": %.12e,\n  \"constraint_violation\": {", sim_.alpha_);
    for (size_t q = 0; q < sc.dbcs.size(); ++q)
      std::fprintf(f, "%s\"dbc%zu\": {\"final\": %.12e, \"max\": %.12e}", q ? ", " : "", q, gaps[q],
                   sim_.maxGap_[q]);
    std::fprintf(f, "},\n");
  }
  std::fprintf(f, "  \"probes\": {");
  for (size_t q = 0; q < probes.size(); ++q) {
    const ProbeState &p = probes[q];
    std::fprintf(f,
                 "%s\n    \"%s\": {\"id\": %lld, \"x0\": [%.12e, %.12e], \"u\": [%.12e, %.12e], "
                 "\"stress\": [%.12e, %.12e, %.12e, %.12e]}",
                 q ? "," : "", sc.probes[q].name.c_str(), static_cast<long long>(p.id), p.X0[0],
                 p.X0[1], p.u[0], p.u[1], p.stress[0], p.stress[1], p.stress[2], p.stress[3]);
  }
  std::fprintf(f, "%s},\n  \"measures\": {", probes.empty() ? "" : "\n  ");
  std::fprintf(f, "\"particles_migrated\": %lld", static_cast<long long>(sim_.migrated_));
  if (std::isnan(sim_.separationStrain_))
    std::fprintf(f, ", \"separation_strain\": null");
  else
    std::fprintf(f, ", \"separation_strain\": %.12e", sim_.separationStrain_);
  std::fprintf(f, ", \"max_strain\": %.12e, \"max_separation\": %.12e", sim_.maxStrain_,
               sim_.maxSeparation_);
  auto num = [](double v) {
    char b[64];
    if (std::isnan(v)) return std::string("null");
    std::snprintf(b, sizeof(b), "%.12e", v);
    return std::string(b);
  };
  if (sc.holeMeasure) {
    std::fprintf(f, ", \"kt\": %s, \"kt_edge\": %s", num(kt).c_str(), num(ktEdge).c_str());
    for (size_t a = 0; a < sim_.hoopByAngle_.size(); ++a)
      std::fprintf(f, ", \"hoop_%zu\": %s", 15 * a, num(sim_.hoopByAngle_[a]).c_str());
  }
  if (sc.mms != Mms::None)
    std::fprintf(f, ", \"mms_linf\": %.12e, \"mms_rms\": %.12e", sim_.mmsLinf_, sim_.mmsRms_);
  std::fprintf(f, "}\n}\n");
  std::fclose(f);
  return PETSC_SUCCESS;
}

} // namespace gimp
