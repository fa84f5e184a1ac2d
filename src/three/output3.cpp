// Output of a 3D run, in the 2D contract's files (docs/output.md): history.csv, summary.json,
// fields.h5 with /particles/step_<n> and particles.xmf (Polyvertex, XYZ geometry) for ParaView.
// Files are written by rank 0 (fields.h5 by every rank through PETSc's HDF5 viewer); a failure
// to write ends every rank with one line.
#include "gimp/core/errors.hpp"
#include "gimp/io/checked.hpp"
#include "gimp/io/json.hpp"
#include "gimp/io/output.hpp"
#include "gimp/three/solver3.hpp"

#include <petscviewerhdf5.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

namespace gimp::three {

namespace {

/// The particle fields a frame holds: name and components.
struct Written {
  const char *name;
  int components;
};
std::vector<Written> writtenFields(bool affine) {
  std::vector<Written> w = {{"x", 3}, {"X0", 3}, {"v", 3},     {"m", 1},
                            {"V", 1}, {"l", 3},  {"stress", 9}};
  if (affine) w.push_back({"B", 9});
  return w;
}

} // namespace

PetscErrorCode Solver3::openOutput() {
  namespace fs = std::filesystem;
  std::string error;
  if (rank_ == 0) {
    std::error_code ec;
    fs::create_directories(sc_.outputDir, ec);
    if (!fs::is_directory(sc_.outputDir, ec))
      error = "option -gimp_output_dir " + sc_.outputDir + ": cannot create the directory";
    for (const char *name :
         {"history.csv", "summary.json", "fields.h5", "particles.xmf", "grid.xmf"})
      if (error.empty()) fs::remove(sc_.outputDir + "/" + name, ec);
    if (error.empty()) {
      history_ = std::fopen((sc_.outputDir + "/history.csv").c_str(), "w");
      if (!history_)
        error = "option -gimp_output_dir " + sc_.outputDir + ": cannot write history.csv (" +
                std::strerror(errno) + ")";
    }
    if (history_) {
      std::fprintf(history_, "step,time,kinetic,strain,external_work,damping,total,momentum_x,"
                             "momentum_y,momentum_z");
      for (const Probe<3> &q : sc_.probes)
        for (const char *c : {"ux", "uy", "uz", "sxx", "syy", "szz", "syz", "sxz", "sxy"})
          std::fprintf(history_, ",%s_%s", q.name.c_str(), c);
      for (size_t q = 0; q < sc_.dbcs.size(); ++q)
        std::fprintf(history_, ",dbc%zu_fx,dbc%zu_fy,dbc%zu_fz", q, q, q);
      if (sc_.mms != Mms::None) std::fprintf(history_, ",mms_linf,mms_rms");
      std::fprintf(history_, "\n");
    }
  }
  PetscCall(agree(comm_, error));
  return PETSC_SUCCESS;
}

PetscErrorCode Solver3::writeHistory(PetscInt step, double t) {
  Energies3 e;
  std::vector<ProbeState3> pr;
  std::vector<double> rf;
  PetscCall(reportState(e, pr, rf));
  double linf = 0, rms = 0;
  PetscCall(mmsErrors(t, linf, rms));
  std::string error;
  if (rank_ == 0) {
    std::fprintf(history_, "%lld,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e,%.12e",
                 static_cast<long long>(step), t, e.kinetic, e.strain, e.externalWork, e.damping,
                 e.total(), e.momentum[0], e.momentum[1], e.momentum[2]);
    for (const ProbeState3 &q : pr) {
      for (double u : q.u)
        std::fprintf(history_, ",%.12e", u);
      for (double s : q.s)
        std::fprintf(history_, ",%.12e", s);
    }
    for (double f : rf)
      std::fprintf(history_, ",%.12e", f);
    if (sc_.mms != Mms::None) std::fprintf(history_, ",%.12e,%.12e", linf, rms);
    std::fprintf(history_, "\n");
    if (std::fflush(history_) != 0)
      error = "option -gimp_output_dir " + sc_.outputDir + ": cannot write history.csv (" +
              std::strerror(errno) + ")";
  }
  PetscCall(agree(comm_, error));
  // The balance watched for growth (diagnostics/energy_watch.hpp): the row that shows it is
  // written, and the run stops as unstable.
  if (!failed_ && energyWatch_.rose(step, e.kinetic, e.strain, e.externalWork, e.damping, e.mass,
                                    sc_.maxWaveSpeed())) {
    failed_ = true;
    failure_ =
        "step " + std::to_string(step) + " t " + formatNumber(t) + " s: " + energyWatch_.why();
    PetscCall(PetscFPrintf(comm_, PETSC_STDERR, "gimp: error: %s\n", failure_.c_str()));
  }
  return PETSC_SUCCESS;
}

PetscErrorCode Solver3::writeFields(PetscInt step, double t) {
  PetscViewer v = nullptr;
  const std::string file = sc_.outputDir + "/fields.h5";
  PetscCall(PetscViewerHDF5Open(comm_, file.c_str(),
                                frames_.empty() ? FILE_MODE_WRITE : FILE_MODE_APPEND, &v));
  PetscCall(PetscViewerHDF5PushGroup(v, ("/particles/" + frameGroup(step)).c_str()));
  PetscInt nloc = 0;
  PetscCall(DMSwarmGetLocalSize(sw_, &nloc));
  for (const Written &w : writtenFields(sc_.transfer == Transfer::Apic)) {
    // A plain MPI Vec over the field's array: an (N, components) dataset.
    PetscScalar *data = nullptr;
    Vec f;
    PetscCall(DMSwarmGetField(sw_, w.name, nullptr, nullptr, reinterpret_cast<void **>(&data)));
    PetscCall(
        VecCreateMPIWithArray(comm_, w.components, w.components * nloc, PETSC_DECIDE, data, &f));
    PetscCall(PetscObjectSetName(reinterpret_cast<PetscObject>(f), w.name));
    PetscCall(VecView(f, v));
    PetscCall(VecDestroy(&f));
    PetscCall(DMSwarmRestoreField(sw_, w.name, nullptr, nullptr, reinterpret_cast<void **>(&data)));
  }
  PetscCall(PetscViewerHDF5WriteAttribute(v, nullptr, "time", PETSC_DOUBLE, &t));
  PetscCall(PetscViewerHDF5PopGroup(v));
  // Each level's nodal velocity and mass: (P, N, M, 3) and (P, N, M) datasets.
  const int K = static_cast<int>(grid_.levels.size());
  std::vector<Vec> vel(K), ms(K);
  PetscCall(DMCompositeGetAccessArray(grid_.dm, vel_, K, nullptr, vel.data()));
  PetscCall(DMCompositeGetAccessArray(grid_.dm, mass_, K, nullptr, ms.data()));
  for (int k = 0; k < K; ++k) {
    Vec m1;
    PetscCall(PetscViewerHDF5PushGroup(
        v, ("/grid/" + frameGroup(step) + "/level_" + std::to_string(k)).c_str()));
    PetscCall(PetscObjectSetName(reinterpret_cast<PetscObject>(vel[k]), "velocity"));
    PetscCall(VecView(vel[k], v));
    PetscCall(DMGetGlobalVector(grid_.da1[k], &m1));
    PetscCall(VecStrideGather(ms[k], 0, m1, INSERT_VALUES));
    PetscCall(PetscObjectSetName(reinterpret_cast<PetscObject>(m1), "mass"));
    PetscCall(VecView(m1, v));
    PetscCall(DMRestoreGlobalVector(grid_.da1[k], &m1));
    PetscCall(PetscViewerHDF5PopGroup(v));
  }
  PetscCall(DMCompositeRestoreAccessArray(grid_.dm, mass_, K, nullptr, ms.data()));
  PetscCall(DMCompositeRestoreAccessArray(grid_.dm, vel_, K, nullptr, vel.data()));
  PetscCall(PetscViewerDestroy(&v));
  frames_.push_back({step, t, static_cast<long long>(nParticles_)});
  return writeXdmf();
}

PetscErrorCode Solver3::writeXdmf() {
  // particles.xmf (Polyvertex, XYZ) and grid.xmf (a 3DCoRectMesh per level), written whole to a
  // temporary file and renamed: a failure leaves the previous version.
  std::string error;
  if (rank_ == 0) {
    const char *head = "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n<Grid "
                       "Name=\"%s\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    const char *tail = "</Grid>\n</Domain>\n</Xdmf>\n";
    for (const char *name : {"particles", "grid"}) {
      const std::string path = sc_.outputDir + "/" + name + ".xmf";
      FILE *f = std::fopen((path + ".tmp").c_str(), "w");
      if (f) {
        std::fprintf(f, head, name);
        for (const Frame &fr : frames_)
          if (std::string(name) == "particles")
            particleXdmf(f, fr);
          else
            gridXdmf(f, fr);
        std::fputs(tail, f);
      }
      if (!f || std::fclose(f) != 0 || std::rename((path + ".tmp").c_str(), path.c_str()) != 0) {
        error = "option -gimp_output_dir " + sc_.outputDir + ": cannot write " + name + ".xmf (" +
                std::strerror(errno) + ")";
        break;
      }
    }
  }
  PetscCall(agree(comm_, error));
  return PETSC_SUCCESS;
}

void Solver3::particleXdmf(FILE *f, const Frame &fr) const {
  const std::string g = frameGroup(fr.step);
  std::fprintf(f,
               " <Grid Name=\"%s\" GridType=\"Uniform\">\n  <Time Value=\"%.12e\"/>\n"
               "  <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"%lld\"/>\n"
               "  <Geometry GeometryType=\"XYZ\"><DataItem Dimensions=\"%lld 3\" "
               "NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">fields.h5:/particles/"
               "%s/x</DataItem></Geometry>\n",
               g.c_str(), fr.t, fr.particles, fr.particles, g.c_str());
  for (const Written &w : writtenFields(sc_.transfer == Transfer::Apic)) {
    if (std::string(w.name) == "x") continue;
    const char *type = w.components == 1 ? "Scalar" : w.components == 3 ? "Vector" : "Tensor";
    const std::string dims = std::to_string(fr.particles) +
                             (w.components == 1 ? "" : " " + std::to_string(w.components));
    std::fprintf(f,
                 "  <Attribute Name=\"%s\" AttributeType=\"%s\" Center=\"Node\"><DataItem "
                 "Dimensions=\"%s\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">"
                 "fields.h5:/particles/%s/%s</DataItem></Attribute>\n",
                 w.name, type, dims.c_str(), g.c_str(), w.name);
  }
  std::fprintf(f, " </Grid>\n");
}

void Solver3::gridXdmf(FILE *f, const Frame &fr) const {
  const std::string g = frameGroup(fr.step);
  std::fprintf(f,
               " <Grid Name=\"%s\" GridType=\"Collection\" CollectionType=\"Spatial\">\n"
               "  <Time Value=\"%.12e\"/>\n",
               g.c_str(), fr.t);
  for (size_t k = 0; k < grid_.levels.size(); ++k) {
    const Level<3> &L = grid_.levels[k];
    const long long P = L.n[2], N = L.n[1], M = L.n[0];
    const std::string ref = "fields.h5:/grid/" + g + "/level_" + std::to_string(k);
    std::fprintf(f,
                 "  <Grid Name=\"level_%zu\" GridType=\"Uniform\">\n"
                 "   <Topology TopologyType=\"3DCoRectMesh\" Dimensions=\"%lld %lld %lld\"/>\n"
                 "   <Geometry GeometryType=\"ORIGIN_DXDYDZ\">\n"
                 "    <DataItem Dimensions=\"3\" NumberType=\"Float\" Format=\"XML\">%.17g %.17g "
                 "%.17g</DataItem>\n"
                 "    <DataItem Dimensions=\"3\" NumberType=\"Float\" Format=\"XML\">%.17g %.17g "
                 "%.17g</DataItem>\n   </Geometry>\n"
                 "   <Attribute Name=\"mass\" AttributeType=\"Scalar\" Center=\"Node\"><DataItem "
                 "Dimensions=\"%lld %lld %lld\" NumberType=\"Float\" Precision=\"8\" "
                 "Format=\"HDF\">%s/mass</DataItem></Attribute>\n"
                 "   <Attribute Name=\"velocity\" AttributeType=\"Vector\" Center=\"Node\">"
                 "<DataItem Dimensions=\"%lld %lld %lld 3\" NumberType=\"Float\" Precision=\"8\" "
                 "Format=\"HDF\">%s/velocity</DataItem></Attribute>\n  </Grid>\n",
                 k, P, N, M, L.box[2], L.box[1], L.box[0], L.h, L.h, L.h, P, N, M, ref.c_str(), P,
                 N, M, ref.c_str());
  }
  std::fprintf(f, " </Grid>\n");
}

PetscErrorCode Solver3::writeParticleDump() {
  // id,x,y,z,vx,vy,vz,sxx,syy,szz,syz,sxz,sxy,V,lx,ly,lz, sorted by id.
  constexpr int kCols = 17;
  ParticleView<3> p;
  PetscCall(p.get(sw_));
  std::vector<double> loc(static_cast<size_t>(p.n) * kCols);
  for (PetscInt k = 0; k < p.n; ++k) {
    double *r = &loc[static_cast<size_t>(k) * kCols];
    const auto s = tensorAt<3>(p.s, k);
    r[0] = static_cast<double>(p.id[k]);
    for (int a = 0; a < 3; ++a) {
      r[1 + a] = p.x[3 * k + a];
      r[4 + a] = p.v[3 * k + a];
      r[14 + a] = p.l[3 * k + a];
    }
    const double six[6] = {s(0, 0), s(1, 1), s(2, 2), s(1, 2), s(0, 2), s(0, 1)};
    std::copy(six, six + 6, r + 7);
    r[13] = p.V[k];
  }
  PetscCall(p.restore(sw_));
  return writeRowsById(comm_, sc_.particleDump,
                       "id,x,y,z,vx,vy,vz,sxx,syy,szz,syz,sxz,sxy,V,lx,ly,lz", kCols, loc);
}

PetscErrorCode Solver3::writeSummary(const std::string &status, PetscInt steps, double t) {
  Energies3 e;
  std::vector<ProbeState3> pr;
  std::vector<double> rf;
  PetscCall(reportState(e, pr, rf));
  PetscLogDouble wall = 0;
  PetscCall(PetscTime(&wall));
  PetscReal dt = 0;
  PetscCall(TSGetTimeStep(ts_, &dt));
  std::string error;
  if (rank_ == 0) {
    using gimp::jsonNumber;
    const std::string path = sc_.outputDir + "/summary.json";
    FILE *f = std::fopen((path + ".tmp").c_str(), "w");
    if (f) {
      std::fprintf(f,
                   "{\n  \"scene\": %s,\n  \"version\": %s,\n  \"dim\": 3,\n  \"status\": %s,\n"
                   "  \"failure\": %s,\n  \"ranks\": %d,\n  \"steps\": %lld,\n  \"time\": %s,\n"
                   "  \"dt\": %s,\n  \"wall_seconds\": %s,\n  \"particles\": %lld,\n"
                   "  \"particle_steps_per_second\": %s,\n",
                   jsonString(sc_.name).c_str(), jsonString(GIMP_VERSION).c_str(),
                   jsonString(status).c_str(), jsonString(failure_).c_str(), size_,
                   static_cast<long long>(steps), jsonNumber(t).c_str(), jsonNumber(dt).c_str(),
                   jsonNumber(wall - wall0_).c_str(), static_cast<long long>(nParticles_),
                   jsonNumber(static_cast<double>(nParticles_) * static_cast<double>(steps) /
                              (wall - wall0_))
                       .c_str());
      std::fprintf(f, "  \"levels\": [");
      for (size_t k = 0; k < grid_.levels.size(); ++k) {
        const Level<3> &L = grid_.levels[k];
        // One level per line, as in 2D (bench/run_bench.sh reads level 0's line).
        std::fprintf(f, "%s\n    {\"h\": %s, \"ratio\": %d, \"box\": [", k ? "," : "",
                     jsonNumber(L.h).c_str(), sc_.levels[k].ratio);
        for (int a = 0; a < 6; ++a)
          std::fprintf(f, "%s%s", a ? ", " : "", jsonNumber(L.box[a]).c_str());
        std::fprintf(f, "], \"nodes\": [%lld, %lld, %lld], \"active_nodes\": %lld}",
                     static_cast<long long>(L.n[0]), static_cast<long long>(L.n[1]),
                     static_cast<long long>(L.n[2]),
                     static_cast<long long>(grid_.activeNodes(static_cast<int>(k))));
      }
      std::fprintf(f,
                   "],\n  \"energy\": {\"kinetic\": %s, \"strain\": %s, \"external_work\": %s, "
                   "\"damping\": %s, \"total\": %s},\n",
                   jsonNumber(e.kinetic).c_str(), jsonNumber(e.strain).c_str(),
                   jsonNumber(e.externalWork).c_str(), jsonNumber(e.damping).c_str(),
                   jsonNumber(e.total()).c_str());
      std::fprintf(f, "  \"momentum\": [%s, %s, %s],\n", jsonNumber(e.momentum[0]).c_str(),
                   jsonNumber(e.momentum[1]).c_str(), jsonNumber(e.momentum[2]).c_str());
      std::fprintf(f, "  \"reactions\": {");
      for (size_t q = 0; q < sc_.dbcs.size(); ++q)
        std::fprintf(f, "%s\"dbc%zu\": [%s, %s, %s]", q ? ", " : "", q,
                     jsonNumber(rf[3 * q]).c_str(), jsonNumber(rf[3 * q + 1]).c_str(),
                     jsonNumber(rf[3 * q + 2]).c_str());
      std::fprintf(f, "},\n  \"penalty\": %s,\n  \"probes\": {", jsonNumber(alpha_).c_str());
      for (size_t q = 0; q < pr.size(); ++q) {
        std::fprintf(f, "%s%s: {\"u\": [", q ? ", " : "", jsonString(sc_.probes[q].name).c_str());
        for (int a = 0; a < 3; ++a)
          std::fprintf(f, "%s%s", a ? ", " : "", jsonNumber(pr[q].u[a]).c_str());
        std::fprintf(f, "], \"stress\": [");
        for (int c = 0; c < 6; ++c)
          std::fprintf(f, "%s%s", c ? ", " : "", jsonNumber(pr[q].s[c]).c_str());
        std::fprintf(f, "]}");
      }
      std::fprintf(f, "},\n  \"measures\": {\"particles_migrated\": %lld",
                   static_cast<long long>(migrated_));
      if (sc_.mms != Mms::None)
        std::fprintf(f, ", \"mms_linf\": %s, \"mms_rms\": %s", jsonNumber(mmsMax_[0]).c_str(),
                     jsonNumber(mmsMax_[1]).c_str());
      std::fprintf(f, "}\n}\n");
    }
    if (!f || std::fclose(f) != 0 || std::rename((path + ".tmp").c_str(), path.c_str()) != 0)
      error = "option -gimp_output_dir " + sc_.outputDir + ": cannot write summary.json (" +
              std::strerror(errno) + ")";
  }
  PetscCall(agree(comm_, error));
  return PETSC_SUCCESS;
}

} // namespace gimp::three
