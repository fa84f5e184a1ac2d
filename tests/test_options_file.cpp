// Unit tests of gimp::expandOptionsFiles (include/gimp/input/options_file.hpp): the command
// line with every -options_file replaced by the file's options, nested files relative to the
// including file, read as PETSc 3.18 reads options files, and one-line errors.
// Each test writes its files in a fresh scratch directory under the system's temp directory.
#include "gimp/input/options_file.hpp"

#include <gtest/gtest.h>

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using Args = std::vector<std::string>;
using gimp::expandOptionsFiles;

class OptionsFile : public ::testing::Test {
protected:
  void SetUp() override {
    const auto *info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("gimp_test_options_file_" + std::to_string(getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    cwd_ = fs::current_path();
  }
  void TearDown() override {
    fs::current_path(cwd_);
    fs::permissions(dir_, fs::perms::owner_all, fs::perm_options::add);
    fs::remove_all(dir_);
  }
  /// Write `text` to dir/name (creating directories); return the full path.
  std::string write(const std::string &name, const std::string &text) {
    const fs::path p = dir_ / name;
    fs::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }
  std::string path(const std::string &name) const { return (dir_ / name).string(); }
  /// The error message of expanding args, or "(no error)".
  static std::string error(const Args &args) {
    try {
      expandOptionsFiles(args);
    } catch (const gimp::InputError &e) {
      return e.what();
    }
    return "(no error)";
  }

  fs::path dir_, cwd_;
};

bool contains(const std::string &s, const std::string &part) {
  return s.find(part) != std::string::npos;
}

TEST_F(OptionsFile, CommandLineWithoutFilesIsKept) {
  EXPECT_EQ(expandOptionsFiles({"-a", "1", "-b", "-c", "-1e-3", "-d", "x y"}),
            (Args{"-a", "1", "-b", "-c", "-1e-3", "-d", "x y"}));
  EXPECT_EQ(expandOptionsFiles({}), Args{});
}

TEST_F(OptionsFile, ReplacedInPlaceSoLaterOptionsOverride) {
  const std::string f = write("scene.opts", "-a 1\n-b 2\n");
  EXPECT_EQ(expandOptionsFiles({"-a", "0", "-options_file", f, "-b", "3"}),
            (Args{"-a", "0", "-a", "1", "-b", "2", "-b", "3"}));
  // The same file twice (one after the other) is no cycle.
  EXPECT_EQ(expandOptionsFiles({"-options_file", f, "-OPTIONS_FILE", f}),
            (Args{"-a", "1", "-b", "2", "-a", "1", "-b", "2"}));
}

TEST_F(OptionsFile, NestedNameIsRelativeToTheIncludingFile) {
  write("scenes/base.opts", "-x 1\n-y 1\n");
  write("scenes/sub/extra.opts", "-w 4\n");
  write("scenes/derived.opts",
        "-pre 0\n-options_file base.opts\n-y 2\n-options_file sub/extra.opts\n");
  const std::string abs = write("elsewhere/abs.opts", "-options_file " + path("scenes/base.opts"));
  fs::create_directories(dir_ / "run");
  fs::current_path(dir_ / "run");
  EXPECT_EQ(expandOptionsFiles({"-options_file", "../scenes/derived.opts", "-y", "3"}),
            (Args{"-pre", "0", "-x", "1", "-y", "1", "-y", "2", "-w", "4", "-y", "3"}));
  EXPECT_EQ(expandOptionsFiles({"-options_file", abs}), (Args{"-x", "1", "-y", "1"}));
  // A file named without a directory includes from the working directory (its directory).
  fs::current_path(dir_ / "scenes");
  EXPECT_EQ(expandOptionsFiles({"-options_file", "derived.opts"}),
            (Args{"-pre", "0", "-x", "1", "-y", "1", "-y", "2", "-w", "4"}));
}

TEST_F(OptionsFile, QuotesAsPetsc) {
  const std::string f = write("q.opts", "-title \"two words\"\n"
                                        "-empty \"\"\n"
                                        "-open \"no end\n" // to the end of the line, blank kept
                                        "-mid a\"b\n"      // PETSc: the value is a
                                        "-neg -2.5\n"
                                        "-flag\n");
  EXPECT_EQ(expandOptionsFiles({"-options_file", f}),
            (Args{"-title", "two words", "-empty", "", "-open", "no end ", "-mid", "a", "-neg",
                  "-2.5", "-flag"}));
}

TEST_F(OptionsFile, CommentsBlanksTabsAndCrlf) {
  const std::string f = write("c.opts", "# a comment\n"
                                        "\n"
                                        "   \t\n"
                                        "  -a 1 # after the value\n"
                                        "-b\t2\r\n"
                                        "-c \"p#q\"\n" // '#' starts a comment even in quotes
                                        "#-d 4\n"
                                        "-e 5"); // no newline at the end
  EXPECT_EQ(expandOptionsFiles({"-options_file", f}),
            (Args{"-a", "1", "-b", "2", "-c", "p", "-e", "5"}));
}

TEST_F(OptionsFile, ByteOrderMarkIsSkipped) {
  const std::string f = write("bom.opts", "\xEF\xBB\xBF-a 1\n-b 2\n");
  EXPECT_EQ(expandOptionsFiles({"-options_file", f}), (Args{"-a", "1", "-b", "2"}));
}

TEST_F(OptionsFile, WordsPetscSkipsAreDropped) {
  const std::string f = write("flag.opts", "-flag\n");
  // A stray word cannot become the value of the file's last option.
  EXPECT_EQ(expandOptionsFiles({"stray", "-options_file", f, "word", "-a", "1"}),
            (Args{"-flag", "-a", "1"}));
}

TEST_F(OptionsFile, YamlIsLeftToPetsc) {
  write("s/y.yaml", "a: 1\n");
  const std::string f = write("s/outer.opts", "-options_file y.yaml\n-b 2\n");
  EXPECT_EQ(expandOptionsFiles({"-options_file", f}),
            (Args{"-options_file", path("s/y.yaml"), "-b", "2"}));
}

TEST_F(OptionsFile, MissingFile) {
  const std::string e = error({"-options_file", path("nope.opts")});
  EXPECT_EQ(e, "option -options_file " + path("nope.opts") +
                   ": cannot open the file (No such file or directory)");
}

TEST_F(OptionsFile, MissingNestedFileSaysWhereItWasNamed) {
  const std::string f = write("a.opts", "-x 1\n\n-options_file gone.opts\n");
  const std::string e = error({"-options_file", f});
  EXPECT_TRUE(contains(e, "option -options_file " + path("gone.opts") + ": cannot open"));
  EXPECT_TRUE(contains(e, "(included from " + f + " line 3)")) << e;
}

TEST_F(OptionsFile, Directory) {
  fs::create_directories(dir_ / "d.opts");
  EXPECT_EQ(error({"-options_file", path("d.opts")}),
            "option -options_file " + path("d.opts") + ": is a directory, not an options file");
}

TEST_F(OptionsFile, Unreadable) {
  // A socket cannot be opened as a file, even by root.
  const std::string s = path("sock.opts");
  const int fd = socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  ASSERT_LT(s.size(), sizeof addr.sun_path);
  s.copy(addr.sun_path, s.size());
  ASSERT_EQ(bind(fd, reinterpret_cast<sockaddr *>(&addr), sizeof addr), 0);
  EXPECT_TRUE(contains(error({"-options_file", s}), ": cannot open the file ("));
  close(fd);
  // Permissions (root reads anyway).
  const std::string f = write("locked.opts", "-a 1\n");
  fs::permissions(f, fs::perms::none);
  if (geteuid() != 0) {
    EXPECT_EQ(error({"-options_file", f}),
              "option -options_file " + f + ": cannot open the file (Permission denied)");
  }
}

TEST_F(OptionsFile, BinaryContent) {
  const std::string f = write("bin.opts", std::string("-a 1\n-b \0\n", 10));
  EXPECT_EQ(error({"-options_file", f}),
            "option -options_file " + f + ": not a text file (NUL byte on line 2)");
}

TEST_F(OptionsFile, IncludesItself) {
  const std::string f = write("self.opts", "-a 1\n-options_file self.opts\n");
  const std::string e = error({"-options_file", f});
  EXPECT_EQ(e, "option -options_file " + f + ": the file includes itself: " + f + " -> " + f +
                   " (included from " + f + " line 2)");
}

TEST_F(OptionsFile, IncludesItselfThroughACycle) {
  const std::string a = write("a.opts", "-options_file sub/b.opts\n");
  const std::string b = write("sub/b.opts", "-options_file ../a.opts\n");
  const std::string e = error({"-options_file", a});
  const std::string back = path("sub/../a.opts");
  EXPECT_TRUE(contains(e, "option -options_file " + back + ": the file includes itself: " + a +
                              " -> " + b + " -> " + back))
      << e;
}

TEST_F(OptionsFile, MissingName) {
  const std::string expected = "option -options_file: missing the file name";
  EXPECT_EQ(error({"-a", "1", "-options_file"}), expected);
  EXPECT_EQ(error({"-options_file", "-a", "1"}), expected);
  const std::string f = write("noname.opts", "-a 1\n-options_file\n");
  EXPECT_EQ(error({"-options_file", f}), expected + " (included from " + f + " line 2)");
}

TEST_F(OptionsFile, NestingDeeperThan16) {
  // f1 includes f2 ... includes fN: 16 files are fine, 17 are not.
  auto chain = [&](int n) {
    for (int i = 1; i <= n; ++i)
      write("n" + std::to_string(n) + "/f" + std::to_string(i) + ".opts",
            "-level" + std::to_string(i) + "\n" +
                (i < n ? "-options_file f" + std::to_string(i + 1) + ".opts\n" : ""));
    return path("n" + std::to_string(n) + "/f1.opts");
  };
  EXPECT_EQ(expandOptionsFiles({"-options_file", chain(16)}).size(), 16u);
  const std::string e = error({"-options_file", chain(17)});
  EXPECT_TRUE(contains(e, "option -options_file " + path("n17/f17.opts") +
                              ": options files nested deeper than 16: " + path("n17/f1.opts") +
                              " -> "))
      << e;
}

TEST_F(OptionsFile, SyntaxErrorsAsPetsc) {
  auto err = [&](const std::string &text) {
    return error({"-options_file", write("bad.opts", "-ok 1\n" + text + "\n")});
  };
  const std::string f = path("bad.opts");
  EXPECT_EQ(err("-a -b"),
            "option -options_file " + f + ": line 2: two options on one line (-a -b)");
  EXPECT_EQ(err("-a 1 2"), "option -options_file " + f + ": line 2: extra token '2' after -a");
  EXPECT_EQ(err("2"),
            "option -options_file " + f +
                ": line 2: '2' is not an option (a value goes on the line of its option)");
  EXPECT_EQ(err("-a 1, 2"), "option -options_file " + f +
                                ": line 2: blank after a comma in the value of -a (write a list "
                                "without blanks: 1,2,3)");
  EXPECT_EQ(err("- 1"), "option -options_file " + f + ": line 2: '-' is not a valid option");
  EXPECT_EQ(err("alias -a -b"),
            "option -options_file " + f + ": line 2: alias lines are not supported");
}

TEST_F(OptionsFile, LauncherRank) {
  const char *names[] = {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"};
  std::vector<std::string> saved;
  for (const char *n : names) {
    const char *v = std::getenv(n);
    saved.push_back(v ? v : "");
    unsetenv(n);
  }
  EXPECT_EQ(gimp::launcherRank(), -1);
  setenv("PMI_RANK", "3", 1);
  EXPECT_EQ(gimp::launcherRank(), 3);
  setenv("OMPI_COMM_WORLD_RANK", "0", 1);
  EXPECT_EQ(gimp::launcherRank(), 0);
  for (int i = 0; i < 3; ++i) {
    if (saved[i].empty())
      unsetenv(names[i]);
    else
      setenv(names[i], saved[i].c_str(), 1);
  }
}

} // namespace

TEST_F(OptionsFile, InputFilePathsAreResolvedBesideTheFile) {
  write("scenes/sub/cap.opts", "-gimp_body0_file disk.csv\n-gimp_restart ../ck.h5\n"
                               "-gimp_body12_FILE /abs/p.csv\n-gimp_output_dir out\n"
                               "-gimp_body0_files x.csv\n");
  write("scenes/top.opts", "-options_file sub/cap.opts\n-gimp_body1_file b.csv\n");
  fs::current_path(dir_);
  EXPECT_EQ(expandOptionsFiles({"-options_file", "scenes/top.opts", "-gimp_body2_file", "c.csv"}),
            (Args{"-gimp_body0_file", "scenes/sub/disk.csv", "-gimp_restart", "scenes/sub/../ck.h5",
                  "-gimp_body12_FILE", "/abs/p.csv", "-gimp_output_dir", "out", "-gimp_body0_files",
                  "x.csv", "-gimp_body1_file", "scenes/b.csv", "-gimp_body2_file", "c.csv"}));
}

TEST_F(OptionsFile, SceneOptionsAreInsertedAfterPetscStarts) {
  const gimp::SplitArgs s = gimp::splitForPetsc(
      {"-log_view", "-gimp_E", "1e7", "-ts_dt", "-1e-3", "-GIMP_flag", "-gimp_nu", "-0.1",
       "-prefix_push", "a_", "-gimp_kept", "1", "-prefix_pop", "-gimp_last", ""});
  EXPECT_EQ(s.early, (Args{"-log_view", "-ts_dt", "-1e-3", "-prefix_push", "a_", "-gimp_kept", "1",
                           "-prefix_pop"}));
  ASSERT_EQ(s.late.size(), 4u);
  EXPECT_EQ(s.late[0].key + "=" + s.late[0].value, "-gimp_E=1e7");
  EXPECT_TRUE(s.late[0].hasValue);
  EXPECT_EQ(s.late[1].key, "-GIMP_flag");
  EXPECT_FALSE(s.late[1].hasValue);
  EXPECT_EQ(s.late[2].key + "=" + s.late[2].value, "-gimp_nu=-0.1");
  EXPECT_EQ(s.late[3].key, "-gimp_last");
  EXPECT_TRUE(s.late[3].hasValue);
  EXPECT_EQ(s.late[3].value, "");
}
