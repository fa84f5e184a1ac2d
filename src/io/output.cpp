#include "gimp/io/output.hpp"

#include "gimp/particles/swarm.hpp"

#include <petscviewerhdf5.h>

#include <cmath>
#include <filesystem>

namespace gimp {

namespace {

std::string groupName(PetscInt step) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "step_%08lld", static_cast<long long>(step));
  return buf;
}

/// The particle fields that the HDF5 output holds for this scene.
std::vector<const FieldSpec *> writtenFields(const Scene &sc) {
  std::vector<const FieldSpec *> out;
  for (const FieldSpec &f : particleFields())
    if (f.written && (!f.cornersOnly || sc.tracking == Tracking::Corners)) out.push_back(&f);
  return out;
}

std::string num(double v) {
  if (!std::isfinite(v)) return "null";
  char b[64];
  std::snprintf(b, sizeof(b), "%.12e", v);
  return b;
}

} // namespace

Output::~Output() {
  if (history_) std::fclose(history_);
}

PetscErrorCode Output::openOnRoot(const std::string &name, FILE **f) const {
  *f = nullptr;
  std::string error;
  if (rank_ == 0) {
    *f = std::fopen((dir_ + "/" + name).c_str(), "w");
    if (!*f) error = "option -gimp_output_dir " + dir_ + ": cannot write " + name + " there";
  }
  PetscCall(agree(comm_, error));
  return PETSC_SUCCESS;
}

PetscErrorCode Output::open(const Resume *resume) {
  PetscCallMPI(MPI_Comm_rank(comm_, &rank_));
  dir_ = sc_.outputDir;
  std::string error;
  if (rank_ == 0) {
    std::error_code ec;
    std::filesystem::create_directories(dir_, ec);
    if (ec) error = "option -gimp_output_dir " + dir_ + ": cannot create it (" + ec.message() + ")";
  }
  PetscCall(agree(comm_, error));
  PetscCall(openOnRoot("history.csv", &history_));
  if (resume) { // a restart: the history up to the checkpoint, the frames it had written
    if (rank_ == 0) {
      std::fwrite(resume->history.data(), 1, resume->history.size(), history_);
      std::fflush(history_);
    }
    return resumeFrames(resume->frames);
  }
  if (rank_ == 0) {
    std::fprintf(history_,
                 "step,time,kinetic,strain,external_work,damping,total,momentum_x,momentum_y,"
                 "separation,strain_x");
    for (const Probe &p : sc_.probes)
      for (const char *c : {"ux", "uy", "sxx", "syy", "sxy", "szz"})
        std::fprintf(history_, ",%s_%s", p.name.c_str(), c);
    for (size_t q = 0; q < sc_.dbcs.size(); ++q)
      std::fprintf(history_, ",dbc%zu_fx,dbc%zu_fy,dbc%zu_gap", q, q, q);
    if (sc_.mms != Mms::None) std::fprintf(history_, ",mms_linf,mms_rms");
    for (const cracks::TipMeasure &m : cracks::tipsOf(sc_))
      for (const char *c : {"G_vcct", "GII_vcct", "G_J", "KI_vcct", "KII_vcct", "KI_J", "KII_J",
                            "opening_n", "opening_t"})
        std::fprintf(history_, ",crack%d_tip%d_%s", m.crack, m.end, c);
    std::fprintf(history_, "\n");
    std::fflush(history_);
    // Remove fields and the checkpoint of an earlier run in the same directory.
    std::error_code ec;
    for (const char *name :
         {"fields.h5", "particles.xmf", "grid.xmf", "checkpoint.h5", "checkpoint.h5.tmp"})
      std::filesystem::remove(dir_ + "/" + name, ec);
  }
  PetscCallMPI(MPI_Barrier(comm_));
  return PETSC_SUCCESS;
}

PetscErrorCode Output::writeHistory(const HistoryRow &r) {
  if (rank_ != 0) return PETSC_SUCCESS;
  const Energies &e = r.energy;
  std::fprintf(history_, "%lld,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e",
               static_cast<long long>(r.step), r.t, e.kinetic, e.strain, e.externalWork, e.damping,
               e.total(), e.momentum[0], e.momentum[1]);
  std::fprintf(history_, ",%.12e,%.12e", r.separation, r.strainX);
  for (const ProbeState &p : r.probes)
    std::fprintf(history_, ",%.12e,%.12e,%.12e,%.12e,%.12e,%.12e", p.u[0], p.u[1], p.stress[0],
                 p.stress[1], p.stress[2], p.stress[3]);
  for (size_t q = 0; q < r.gaps.size(); ++q)
    std::fprintf(history_, ",%.12e,%.12e,%.12e", r.reactions[2 * q], r.reactions[2 * q + 1],
                 r.gaps[q]);
  if (sc_.mms != Mms::None) std::fprintf(history_, ",%.12e,%.12e", r.mmsLinf, r.mmsRms);
  for (const cracks::TipMeasure &m : r.tips)
    std::fprintf(history_, ",%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e", m.G_vcct,
                 m.GII_vcct, m.G_J, m.KI_vcct, m.KII_vcct, m.KI_J, m.KII_J, m.opening[0],
                 m.opening[1]);
  std::fprintf(history_, "\n");
  std::fflush(history_);
  return PETSC_SUCCESS;
}

PetscErrorCode Output::writeFields(PetscInt step, double t, DM sw, Vec velocity, Vec mass) {
  PetscViewer v;
  const std::string file = dir_ + "/fields.h5";
  PetscCall(PetscViewerHDF5Open(comm_, file.c_str(),
                                frames_.empty() ? FILE_MODE_WRITE : FILE_MODE_APPEND, &v));
  const std::string g = groupName(step);
  PetscCall(PetscViewerHDF5PushGroup(v, ("/particles/" + g).c_str()));
  PetscInt nloc = 0;
  PetscCall(DMSwarmGetLocalSize(sw, &nloc));
  for (const FieldSpec *fs : writtenFields(sc_)) {
    // A plain MPI Vec over the field array: written as an (N, components) dataset.
    PetscScalar *data = nullptr;
    Vec f;
    const PetscInt bs = fs->components;
    PetscCall(DMSwarmGetField(sw, fs->name, nullptr, nullptr, reinterpret_cast<void **>(&data)));
    PetscCall(VecCreateMPIWithArray(comm_, bs, bs * nloc, PETSC_DECIDE, data, &f));
    PetscCall(PetscObjectSetName(reinterpret_cast<PetscObject>(f), fs->name));
    PetscCall(VecView(f, v));
    PetscCall(VecDestroy(&f));
    PetscCall(
        DMSwarmRestoreField(sw, fs->name, nullptr, nullptr, reinterpret_cast<void **>(&data)));
  }
  PetscCall(PetscViewerHDF5WriteAttribute(v, nullptr, "time", PETSC_DOUBLE, &t));
  PetscCall(PetscViewerHDF5PopGroup(v));
  // Grid: each level's velocity and mass as (N, M[, 2]) datasets.
  const int K = static_cast<int>(grid_.levels.size());
  std::vector<Vec> vel(K), ms(K);
  PetscCall(DMCompositeGetAccessArray(grid_.dm, velocity, K, nullptr, vel.data()));
  PetscCall(DMCompositeGetAccessArray(grid_.dm, mass, K, nullptr, ms.data()));
  for (int k = 0; k < K; ++k) {
    Vec m1;
    PetscCall(PetscViewerHDF5PushGroup(v, ("/grid/" + g + "/level_" + std::to_string(k)).c_str()));
    PetscCall(PetscObjectSetName(reinterpret_cast<PetscObject>(vel[k]), "velocity"));
    PetscCall(VecView(vel[k], v));
    PetscCall(DMGetGlobalVector(grid_.da1[k], &m1));
    PetscCall(VecStrideGather(ms[k], 0, m1, INSERT_VALUES));
    PetscCall(PetscObjectSetName(reinterpret_cast<PetscObject>(m1), "mass"));
    PetscCall(VecView(m1, v));
    PetscCall(DMRestoreGlobalVector(grid_.da1[k], &m1));
    PetscCall(PetscViewerHDF5PopGroup(v));
  }
  PetscCall(DMCompositeRestoreAccessArray(grid_.dm, mass, K, nullptr, ms.data()));
  PetscCall(DMCompositeRestoreAccessArray(grid_.dm, velocity, K, nullptr, vel.data()));
  PetscCall(PetscViewerDestroy(&v));
  PetscInt64 n = nloc, total = 0;
  PetscCallMPI(MPI_Allreduce(&n, &total, 1, MPI_INT64_T, MPI_SUM, comm_));
  frames_.push_back({step, t, static_cast<long long>(total)});
  PetscCall(writeXdmf());
  return PETSC_SUCCESS;
}

PetscErrorCode Output::writeXdmf() const {
  FILE *fp = nullptr, *fg = nullptr;
  PetscCall(openOnRoot("particles.xmf", &fp));
  PetscCall(openOnRoot("grid.xmf", &fg));
  if (rank_ != 0) return PETSC_SUCCESS;
  const char *head = "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n"
                     "<Grid Name=\"%s\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  const char *tail = "</Grid>\n</Domain>\n</Xdmf>\n";
  std::fprintf(fp, head, "particles");
  std::fprintf(fg, head, "grid");
  PetscCall(writeParticleXdmf(fp));
  PetscCall(writeGridXdmf(fg));
  std::fputs(tail, fp);
  std::fputs(tail, fg);
  std::fclose(fp);
  std::fclose(fg);
  return PETSC_SUCCESS;
}

PetscErrorCode Output::writeParticleXdmf(FILE *fp) const {
  for (const Frame &fr : frames_) {
    const std::string g = groupName(fr.step);
    std::fprintf(fp,
                 " <Grid Name=\"%s\" GridType=\"Uniform\">\n  <Time Value=\"%.12e\"/>\n"
                 "  <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"%lld\"/>\n"
                 "  <Geometry GeometryType=\"XY\"><DataItem Dimensions=\"%lld 2\" "
                 "NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">fields.h5:/particles/%s/x"
                 "</DataItem></Geometry>\n",
                 g.c_str(), fr.t, fr.particles, fr.particles, g.c_str());
    for (const FieldSpec *fs : writtenFields(sc_)) {
      if (std::string(fs->name) == "x") continue;
      const std::string dims =
          fs->components == 1 ? "" : " " + std::to_string(static_cast<int>(fs->components));
      std::fprintf(fp,
                   "  <Attribute Name=\"%s\" AttributeType=\"%s\" Center=\"Node\"><DataItem "
                   "Dimensions=\"%lld%s\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">"
                   "fields.h5:/particles/%s/%s</DataItem></Attribute>\n",
                   fs->name, fs->components == 1 ? "Scalar" : "Matrix", fr.particles, dims.c_str(),
                   g.c_str(), fs->name);
    }
    std::fprintf(fp, " </Grid>\n");
  }
  return PETSC_SUCCESS;
}

PetscErrorCode Output::writeGridXdmf(FILE *fg) const {
  for (const Frame &fr : frames_) {
    const std::string g = groupName(fr.step);
    std::fprintf(fg,
                 " <Grid Name=\"%s\" GridType=\"Collection\" CollectionType=\"Spatial\">\n"
                 "  <Time Value=\"%.12e\"/>\n",
                 g.c_str(), fr.t);
    for (size_t k = 0; k < grid_.levels.size(); ++k) {
      const Level &L = grid_.levels[k];
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
  return PETSC_SUCCESS;
}

PetscErrorCode Output::writeHoop(const HoleMeasure &h) {
  FILE *f = nullptr;
  PetscCall(openOnRoot("hoop.csv", &f));
  if (rank_ != 0) return PETSC_SUCCESS;
  std::fprintf(f, "angle_deg,r,hoop_over_p,kirsch\n");
  for (const std::vector<double> &r : h.rows)
    std::fprintf(f, "%.6f,%.9e,%.9e,%.9e\n", r[0], r[1], r[2], r[3]);
  std::fclose(f);
  return PETSC_SUCCESS;
}

PetscErrorCode Output::writeSummary(const SummaryReport &r) {
  FILE *f = nullptr;
  PetscCall(openOnRoot("summary.json", &f));
  if (rank_ != 0) return PETSC_SUCCESS;
  summaryRun(f, r);
  summaryState(f, r);
  summaryMeasures(f, r);
  std::fprintf(f, "\n}\n");
  std::fclose(f);
  return PETSC_SUCCESS;
}

void Output::summaryRun(FILE *f, const SummaryReport &r) const {
  std::fprintf(f, "{\n  \"scene\": \"%s\",\n  \"version\": \"%s\",\n  \"status\": \"%s\",\n",
               sc_.name.c_str(), GIMP_VERSION, r.status.c_str());
  std::fprintf(f,
               "  \"ranks\": %d,\n  \"steps\": %lld,\n  \"time\": %.12e,\n  \"dt\": %.12e,\n"
               "  \"wall_seconds\": %.6f,\n  \"cpu_seconds\": %.6f,\n  \"particles\": %lld,\n",
               r.ranks, static_cast<long long>(r.steps), r.t, r.dt, r.wallSeconds, r.cpuSeconds,
               static_cast<long long>(r.particles));
  std::fprintf(f, "  \"levels\": [");
  for (size_t k = 0; k < grid_.levels.size(); ++k) {
    const Level &L = grid_.levels[k];
    std::fprintf(f,
                 "%s\n    {\"h\": %.12e, \"ratio\": %d, \"box\": [%.12e, %.12e, %.12e, %.12e], "
                 "\"nodes\": [%lld, %lld], \"active_nodes\": %lld}",
                 k ? "," : "", L.h, k ? sc_.levels[k].ratio : 1, L.box[0], L.box[1], L.box[2],
                 L.box[3], static_cast<long long>(L.M), static_cast<long long>(L.N),
                 static_cast<long long>(grid_.activeNodes(static_cast<int>(k))));
  }
  std::fprintf(f, "],\n");
}

void Output::summaryState(FILE *f, const SummaryReport &r) const {
  const Energies &e = r.energy;
  std::fprintf(f,
               "  \"energy\": {\"kinetic\": %.12e, \"strain\": %.12e, \"external_work\": %.12e, "
               "\"damping\": %.12e},\n",
               e.kinetic, e.strain, e.externalWork, e.damping);
  std::fprintf(f, "  \"momentum\": [%.12e, %.12e],\n", e.momentum[0], e.momentum[1]);
  std::fprintf(f, "  \"reactions\": {");
  for (size_t q = 0; q < sc_.dbcs.size(); ++q)
    std::fprintf(f, "%s\"dbc%zu\": [%.12e, %.12e]", q ? ", " : "", q, r.reactions[2 * q],
                 r.reactions[2 * q + 1]);
  std::fprintf(f, "},\n");
  if (!sc_.dbcs.empty()) {
    std::fprintf(f, "  \"penalty\": %.12e,\n  \"constraint_violation\": {", r.penalty);
    for (size_t q = 0; q < sc_.dbcs.size(); ++q)
      std::fprintf(f, "%s\"dbc%zu\": {\"final\": %.12e, \"max\": %.12e}", q ? ", " : "", q,
                   r.gaps[q], r.maxGaps[q]);
    std::fprintf(f, "},\n");
  }
  std::fprintf(f, "  \"probes\": {");
  for (size_t q = 0; q < r.probes.size(); ++q) {
    const ProbeState &p = r.probes[q];
    std::fprintf(f,
                 "%s\n    \"%s\": {\"id\": %lld, \"x0\": [%.12e, %.12e], \"u\": [%.12e, %.12e], "
                 "\"stress\": [%.12e, %.12e, %.12e, %.12e]}",
                 q ? "," : "", sc_.probes[q].name.c_str(), static_cast<long long>(p.id), p.X0[0],
                 p.X0[1], p.u[0], p.u[1], p.stress[0], p.stress[1], p.stress[2], p.stress[3]);
  }
}

void Output::summaryMeasures(FILE *f, const SummaryReport &r) const {
  const RunMeasures &m = r.measures;
  std::fprintf(f, "%s},\n  \"measures\": {", r.probes.empty() ? "" : "\n  ");
  std::fprintf(f, "\"particles_migrated\": %lld", static_cast<long long>(m.migrated));
  std::fprintf(f, ", \"separation_strain\": %s", num(m.separationStrain).c_str());
  std::fprintf(f, ", \"max_strain\": %.12e, \"max_separation\": %.12e", m.maxStrain,
               m.maxSeparation);
  if (r.hole) {
    std::fprintf(f, ", \"kt\": %s, \"kt_edge\": %s", num(r.hole->kt).c_str(),
                 num(r.hole->ktEdge).c_str());
    for (size_t a = 0; a < r.hole->hoopByAngle.size(); ++a)
      std::fprintf(f, ", \"hoop_%zu\": %s", 15 * a, num(r.hole->hoopByAngle[a]).c_str());
  }
  if (sc_.mms != Mms::None)
    std::fprintf(f, ", \"mms_linf\": %.12e, \"mms_rms\": %.12e", m.mmsLinf, m.mmsRms);
  std::fprintf(f, "}");
  if (!r.tips.empty()) {
    std::fprintf(f, ",\n  \"cracks\": [");
    for (size_t q = 0; q < r.tips.size(); ++q) {
      const cracks::TipMeasure &m = r.tips[q];
      std::fprintf(
          f,
          "%s\n    {\"crack\": %d, \"end\": %d, \"tip\": [%s, %s], \"G_vcct\": %s, "
          "\"GII_vcct\": %s, \"G_J\": %s, \"KI_vcct\": %s, \"KII_vcct\": %s, \"KI_J\": %s, "
          "\"KII_J\": %s, \"h\": %s, \"opening\": [%s, %s]}",
          q ? "," : "", m.crack, m.end, num(m.tip[0]).c_str(), num(m.tip[1]).c_str(),
          num(m.G_vcct).c_str(), num(m.GII_vcct).c_str(), num(m.G_J).c_str(),
          num(m.KI_vcct).c_str(), num(m.KII_vcct).c_str(), num(m.KI_J).c_str(),
          num(m.KII_J).c_str(), num(m.h).c_str(), num(m.opening[0]).c_str(),
          num(m.opening[1]).c_str());
    }
    std::fprintf(f, "]");
  }
}

} // namespace gimp
