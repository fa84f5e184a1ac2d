// Expansion of -options_file before PETSc starts; see include/gimp/input/options_file.hpp.
// The reading follows PETSc 3.18's src/sys/objects/options.c: PetscOptionsInsertFilePetsc
// (lines to a string of options with quoted values), PetscOptionsInsertString (that string to
// options), PetscOptionsInsertArgs (the command line), PetscTokenFind, PetscOptionsValidKey.
#include "gimp/input/options_file.hpp"

#include <strings.h>
#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

namespace gimp {
namespace {

/// PetscOptionsValidKey: '-' (or "--") and a letter, and not a number such as -1e3 or -inf.
bool isKey(const std::string &s) {
  const char *key = s.c_str();
  if (key[0] != '-') return false;
  if (key[1] == '-') ++key;
  if (!std::isalpha(static_cast<unsigned char>(key[1]))) return false;
  char *end = nullptr;
  (void)std::strtod(key, &end);
  return end == key || *end == '_' || std::isalnum(static_cast<unsigned char>(*end));
}

bool is(const std::string &s, const char *name) {
  return strcasecmp(s.c_str(), name) == 0;
}

bool endsWith(const std::string &s, const char *tail) {
  const std::size_t n = std::strlen(tail);
  return s.size() >= n && s.compare(s.size() - n, n, tail) == 0;
}

/// An option that names a file the run reads (-gimp_bodyK_file, -gimp_restart): in an options
/// file a relative path is resolved beside that file, as a nested -options_file is.
bool isInputFile(const std::string &key) {
  std::string k = key.substr(key.compare(0, 2, "--") == 0 ? 2 : 1);
  for (char &c : k)
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (k == "gimp_restart") return true;
  const std::string head = "gimp_body", tail = "_file";
  if (k.size() <= head.size() + tail.size() || k.compare(0, head.size(), head) != 0 ||
      !endsWith(k, tail.c_str()))
    return false;
  const std::string index = k.substr(head.size(), k.size() - head.size() - tail.size());
  return std::all_of(index.begin(), index.end(),
                     [](char c) { return std::isdigit(static_cast<unsigned char>(c)); });
}

/// `name` relative to the directory `dir` of the file that gave it, unless absolute.
std::string beside(const std::string &dir, const std::string &name) {
  if (dir.empty() || name.empty() || name[0] == '/') return name;
  return (std::filesystem::path(dir) / name).string();
}

/// PetscTokenFind with separator ' ': tokens are separated by runs of blanks; a token that
/// starts with '"' runs to the next '"' (or to the end) without its quotes. A string that
/// starts with a blank gives an empty first token.
class Tokens {
public:
  explicit Tokens(const std::string &s) : s_(s) {}
  bool next(std::string &token) {
    if (pos_ == std::string::npos || pos_ == s_.size()) return false;
    std::size_t p = pos_;
    const char end = s_[p] == '"' ? '"' : ' ';
    if (end == '"') ++p;
    start_ = p;
    for (;; ++p) {
      if (p == s_.size()) {
        pos_ = std::string::npos;
        break;
      }
      if (s_[p] == end) {
        pos_ = p + 1;
        while (pos_ < s_.size() && s_[pos_] == ' ')
          ++pos_;
        break;
      }
    }
    token = s_.substr(start_, p - start_);
    return true;
  }
  std::size_t start() const { return start_; } // where the last token began

private:
  const std::string &s_;
  std::size_t pos_ = 0, start_ = 0;
};

/// One file's options as PetscOptionsInsertFilePetsc packs them: `-key "value" ` per line,
/// with the line each entry came from.
struct Packed {
  std::string text;
  std::vector<std::pair<std::size_t, int>> lines; // (offset in text, line number)
  int lineAt(std::size_t offset) const {
    int line = 0;
    for (const auto &[start, n] : lines)
      if (start <= offset) line = n;
    return line;
  }
};

struct FileId {
  dev_t dev;
  ino_t ino;
  bool operator==(const FileId &o) const { return dev == o.dev && ino == o.ino; }
};

class Expander {
public:
  std::vector<std::string> out;

  /// PetscOptionsInsertArgs over the command line.
  void commandLine(const std::vector<std::string> &args) {
    for (std::size_t i = 0; i < args.size();) {
      const std::string &a = args[i];
      const bool hasNext = i + 1 < args.size();
      if (!isKey(a)) {
        ++i; // PETSc skips a word where an option is expected
      } else if (is(a, "-options_file")) {
        if (!hasNext || args[i + 1].empty() || args[i + 1][0] == '-')
          fail("", "missing the file name", "");
        include(args[i + 1], "", "");
        i += 2;
      } else {
        const bool takesNext = is(a, "-prefix_push") || is(a, "-options_file_yaml") ||
                               is(a, "-options_string_yaml") ||
                               (!is(a, "-prefix_pop") && hasNext && !isKey(args[i + 1]));
        out.push_back(a);
        if (takesNext && hasNext) out.push_back(args[i + 1]);
        i += takesNext && hasNext ? 2 : 1;
      }
    }
  }

private:
  struct Open {
    std::string path;
    FileId id;
  };
  std::vector<Open> open_; // the files being read, outermost first

  [[noreturn]] static void fail(const std::string &name, const std::string &what,
                                const std::string &where) {
    throw InputError("option -options_file" + (name.empty() ? "" : " " + name) + ": " + what +
                     where);
  }

  std::string chain(const std::string &last) const {
    std::string s;
    for (const Open &o : open_)
      s += o.path + " -> ";
    return s + last;
  }

  void passToPetsc(const std::string &path) {
    out.push_back("-options_file");
    out.push_back(path);
  }

  /// Read the file `name`, relative to `dir` unless absolute, and append its options.
  /// `where` says which file and line named it (empty on the command line).
  void include(const std::string &name, const std::string &dir, const std::string &where) {
    if (name.find("${") != std::string::npos) return passToPetsc(name);
    const std::string path =
        dir.empty() || name[0] == '/' ? name : (std::filesystem::path(dir) / name).string();
    if (endsWith(path, ".yaml") || endsWith(path, ".yml") || endsWith(path, ".json") ||
        endsWith(path, ":yaml"))
      return passToPetsc(path);

    struct stat st {};
    if (stat(path.c_str(), &st) != 0)
      fail(path, std::string("cannot open the file (") + std::strerror(errno) + ")", where);
    if (S_ISDIR(st.st_mode)) fail(path, "is a directory, not an options file", where);
    const FileId id{st.st_dev, st.st_ino};
    for (const Open &o : open_)
      if (o.id == id) fail(path, "the file includes itself: " + chain(path), where);
    if (static_cast<int>(open_.size()) >= kMaxOptionsFileDepth)
      fail(path,
           "options files nested deeper than " + std::to_string(kMaxOptionsFileDepth) + ": " +
               chain(path),
           where);

    const std::string content = read(path, where);
    if (content.compare(0, 6, "%YAML ") == 0 || content.compare(0, 3, "---") == 0)
      return passToPetsc(path);
    const Packed packed = pack(path, content, where);

    // PetscOptionsInsertString over the packed options.
    open_.push_back({path, id});
    const std::string base = std::filesystem::path(path).parent_path().string();
    Tokens tokens(packed.text);
    std::string first, second;
    bool more = tokens.next(first);
    while (more) {
      if (!isKey(first)) {
        more = tokens.next(first);
      } else if (is(first, "-options_file")) {
        const int line = packed.lineAt(tokens.start());
        const std::string here = " (included from " + path + " line " + std::to_string(line) + ")";
        if (!tokens.next(second) || second.empty()) fail("", "missing the file name", here);
        include(second, base, here);
        more = tokens.next(first);
      } else if (is(first, "-prefix_push") || is(first, "-options_file_yaml") ||
                 is(first, "-options_string_yaml")) {
        out.push_back(first);
        if (tokens.next(second)) out.push_back(second);
        more = tokens.next(first);
      } else if (is(first, "-prefix_pop")) {
        out.push_back(first);
        more = tokens.next(first);
      } else {
        out.push_back(first);
        more = tokens.next(second);
        if (more && !isKey(second)) {
          out.push_back(isInputFile(first) ? beside(base, second) : second);
          more = tokens.next(first);
        } else {
          first = second;
        }
      }
    }
    open_.pop_back();
  }

  static std::string read(const std::string &path, const std::string &where) {
    std::FILE *f = std::fopen(path.c_str(), "rb");
    if (!f) fail(path, std::string("cannot open the file (") + std::strerror(errno) + ")", where);
    std::string content;
    char buf[65536];
    std::size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, f)) > 0)
      content.append(buf, n);
    const int error = std::ferror(f) ? errno : 0;
    std::fclose(f);
    if (error)
      fail(path, std::string("cannot read the file (") + std::strerror(error) + ")", where);
    const std::size_t nul = content.find('\0');
    if (nul != std::string::npos) {
      const long line = 1 + std::count(content.begin(), content.begin() + nul, '\n');
      fail(path, "not a text file (NUL byte on line " + std::to_string(line) + ")", where);
    }
    return content;
  }

  /// PetscOptionsInsertFilePetsc: each line to `-key "value" `, checked as PETSc checks it.
  static Packed pack(const std::string &path, const std::string &content,
                     const std::string &where) {
    Packed packed;
    std::size_t at = content.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0; // UTF-8 BOM
    for (int number = 1; at < content.size(); ++number) {
      const std::size_t eol = content.find('\n', at);
      const std::size_t end = eol == std::string::npos ? content.size() : eol + 1;
      std::string line = content.substr(at, end - at);
      at = end;
      line = line.substr(0, line.find('#'));
      for (char &c : line)
        if (c == '\t' || c == '\r' || c == '\n') c = ' ';
      Tokens tokens(line);
      std::string t[4];
      bool has[4] = {tokens.next(t[0]), false, false, false};
      if (has[0] && t[0].empty()) has[0] = tokens.next(t[0]);
      if (!has[0]) continue;
      for (int i = 1; i < 4; ++i)
        has[i] = tokens.next(t[i]);
      const std::string at_line = "line " + std::to_string(number) + ": ";
      if (t[0][0] != '-') {
        if (is(t[0], "alias")) fail(path, at_line + "alias lines are not supported", where);
        fail(path,
             at_line + "'" + t[0] + "' is not an option" +
                 (packed.text.empty() ? "" : " (a value goes on the line of its option)"),
             where);
      }
      if (!isKey(t[0])) fail(path, at_line + "'" + t[0] + "' is not a valid option", where);
      if (has[1] && isKey(t[1]))
        fail(path, at_line + "two options on one line (" + t[0] + " " + t[1] + ")", where);
      if (has[2] && !t[1].empty() && t[1].back() == ',')
        fail(path,
             at_line + "blank after a comma in the value of " + t[0] +
                 " (write a list without blanks: 1,2,3)",
             where);
      if (has[2]) fail(path, at_line + "extra token '" + t[2] + "' after " + t[0], where);
      packed.lines.emplace_back(packed.text.size(), number);
      packed.text += t[0] + " ";
      if (has[1]) packed.text += "\"" + t[1] + "\" ";
    }
    return packed;
  }
};

} // namespace

std::vector<std::string> expandOptionsFiles(const std::vector<std::string> &args) {
  Expander e;
  e.commandLine(args);
  return std::move(e.out);
}

SplitArgs splitForPetsc(const std::vector<std::string> &expanded) {
  SplitArgs split;
  int prefixes = 0; // -prefix_push depth
  for (std::size_t i = 0; i < expanded.size();) {
    const std::string &a = expanded[i];
    const bool valueNext = i + 1 < expanded.size() && !isKey(expanded[i + 1]);
    std::string lower = a;
    for (char &c : lower)
      c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (isKey(a) && prefixes == 0 && lower.compare(0, 6, "-gimp_") == 0) {
      split.late.push_back({a, valueNext ? expanded[i + 1] : "", valueNext});
      i += valueNext ? 2 : 1;
      continue;
    }
    if (is(a, "-prefix_push")) ++prefixes;
    if (is(a, "-prefix_pop") && prefixes > 0) --prefixes;
    const bool takesNext = is(a, "-prefix_push") || is(a, "-options_file_yaml") ||
                           is(a, "-options_string_yaml") ||
                           (isKey(a) && !is(a, "-prefix_pop") && valueNext);
    split.early.push_back(a);
    if (takesNext && i + 1 < expanded.size()) split.early.push_back(expanded[++i]);
    ++i;
  }
  return split;
}

int launcherRank() {
  for (const char *name : {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"}) {
    const char *value = std::getenv(name);
    if (value && *value) return std::atoi(value);
  }
  return -1;
}

} // namespace gimp
