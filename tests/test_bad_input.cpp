// Bad input, in process: every case of tests/bad_input/cases2d.tsv and cases3d.tsv sets up the
// solver of its scene with the case's options (as gimp's main would: options files expanded,
// then the scene read, the grid, particles and time stepper built and checked) and must stop with
// one InputError whose line holds the case's text; a case whose setup succeeds, or stops with a
// PETSc error instead, fails. One process runs them all (tests/check_input.py and
// check_input3d.py run what needs processes: exit codes, one line under mpiexec, options files).
//
//   test_bad_input ROOT WORK   (ROOT: the repository, WORK: a scratch directory)
#include "gimp/input/options_file.hpp"
#include "gimp/solver/solver.hpp"

#include <gtest/gtest.h>
#include <petscsys.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

std::string gRoot = ".", gWork = "/tmp";

struct Case {
  std::string name, scene, options, needle;
};

std::vector<Case> readCases(const std::string &file) {
  std::vector<Case> cases;
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream f(line);
    Case c;
    std::getline(f, c.name, '\t');
    std::getline(f, c.scene, '\t');
    std::getline(f, c.options, '\t');
    std::getline(f, c.needle, '\t');
    cases.push_back(c);
  }
  return cases;
}

/// The solver of dimension D set up on the options now in the database; the error line, or ""
/// when setup succeeded (a PETSc error: "PETSc error <code>").
template <int D> std::string setupError() {
  try {
    gimp::Solver<D> sim(PETSC_COMM_WORLD);
    const PetscErrorCode ierr = sim.setup();
    return ierr ? "PETSc error " + std::to_string(static_cast<int>(ierr)) : "";
  } catch (const gimp::InputError &e) {
    return e.what();
  }
}

/// The case's options in the database (the scene's file expanded, then the case's, a one-step
/// run into the scratch directory), and the error its setup stops with.
std::string errorOf(const Case &c) {
  std::vector<std::string> args = {"-options_file", gRoot + "/" + c.scene};
  std::istringstream words(c.options);
  for (std::string w; words >> w;)
    args.push_back(w);
  for (const char *w : {"-ts_max_steps", "1", "-gimp_output_dir"})
    args.push_back(w);
  args.push_back(gWork + "/bad_input");
  std::vector<std::string> expanded;
  try {
    expanded = gimp::expandOptionsFiles(args);
  } catch (const gimp::InputError &e) {
    return e.what();
  }
  std::string line;
  int dim = 2;
  for (size_t i = 0; i < expanded.size(); ++i) {
    line += " " + expanded[i];
    if (expanded[i] == "-gimp_dim" && i + 1 < expanded.size() && expanded[i + 1] == "3") dim = 3;
  }
  if (PetscOptionsClear(nullptr) || PetscOptionsInsertString(nullptr, line.c_str()))
    return "PETSc error inserting the options";
  const std::string error = dim == 3 ? setupError<3>() : setupError<2>();
  (void)PetscOptionsClear(nullptr);
  return error;
}

class BadInput : public ::testing::TestWithParam<std::string> {};

TEST_P(BadInput, EveryCaseStopsWithItsLine) {
  const std::vector<Case> cases = readCases(gRoot + "/tests/bad_input/" + GetParam());
  ASSERT_GT(cases.size(), 10u) << "no cases read from " << GetParam();
  for (const Case &c : cases) {
    const std::string error = errorOf(c);
    EXPECT_NE(error.find(c.needle), std::string::npos)
        << c.name << ": wanted a line with \"" << c.needle << "\", got \""
        << (error.empty() ? "(setup succeeded)" : error) << "\"";
    EXPECT_EQ(error.find('\n'), std::string::npos) << c.name << ": more than one line";
  }
}

INSTANTIATE_TEST_SUITE_P(Tables, BadInput, ::testing::Values("cases2d.tsv", "cases3d.tsv"));

} // namespace

int main(int argc, char **argv) {
  ::testing::InitGoogleTest(&argc, argv);
  if (argc > 1) gRoot = argv[1];
  if (argc > 2) gWork = argv[2];
  int one = 1;
  char *none[] = {argv[0], nullptr};
  char **pargv = none;
  if (PetscInitialize(&one, &pargv, nullptr, nullptr)) return 1;
  const int result = RUN_ALL_TESTS();
  if (PetscFinalize()) return 1;
  return result;
}
