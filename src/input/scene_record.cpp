// The scene a checkpoint belongs to (input/scene_record.hpp): the state-defining options as
// canonical text, and the first difference between two such records.
#include "gimp/input/scene_record.hpp"

#include "gimp/input/options.hpp"

#include <petscsys.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

namespace gimp::input {

namespace {

/// The options a restart may change: step limits, outputs and resources (docs/output.md).
const std::set<std::string> kKept = {"gimp_options_markdown",
                                     "gimp_scene",
                                     "gimp_output_dir",
                                     "gimp_output_interval",
                                     "gimp_history_interval",
                                     "gimp_monitor_interval",
                                     "gimp_checkpoint_interval",
                                     "gimp_restart",
                                     "gimp_particle_dump",
                                     "gimp_grid_dump",
                                     "gimp_lanes",
                                     "gimp_balance",
                                     "gimp_memory_limit"};

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return s;
}

std::string trim(const std::string &s) {
  const size_t a = s.find_first_not_of(" \t"), b = s.find_last_not_of(" \t");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

/// A number in its shortest form that reads back to the same double ("" if `s` is none).
std::string number(const std::string &s) {
  const std::string t = trim(s);
  char *end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  if (t.empty() || *end != '\0') return "";
  char buf[40];
  for (int p = 1; p <= 17; ++p) {
    std::snprintf(buf, sizeof buf, "%.*g", p, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

/// FNV-1a of the file's bytes, in hex ("unreadable" when it cannot be read).
std::string contentHash(const std::string &path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "unreadable";
  unsigned long long h = 14695981039346656037ull;
  char buf[65536];
  while (in.read(buf, sizeof buf) || in.gcount() > 0) {
    for (std::streamsize i = 0; i < in.gcount(); ++i) {
      h ^= static_cast<unsigned char>(buf[i]);
      h *= 1099511628211ull;
    }
    if (!in) break;
  }
  char hex[24];
  std::snprintf(hex, sizeof hex, "%016llx", h);
  return std::string("content ") + hex;
}

/// The canonical text of `value` for option s (its text as given when it does not parse).
std::string canonical(const OptionSpec &s, const std::string &value) {
  const std::string t = trim(value);
  switch (s.kind) {
  case Kind::Real:
  case Kind::Int: {
    const std::string n = number(t);
    return n.empty() ? t : n;
  }
  case Kind::Reals:
  case Kind::Ramp: {
    std::string out, item;
    std::istringstream in(t);
    while (std::getline(in, item, ',')) {
      const std::string n = number(item);
      out += (out.empty() ? "" : ",") + (n.empty() ? trim(item) : n);
    }
    return out;
  }
  case Kind::Bool: {
    const std::string b = lower(t);
    if (b.empty() || b == "true" || b == "yes" || b == "on" || b == "1") return "true";
    if (b == "false" || b == "no" || b == "off" || b == "0") return "false";
    return b;
  }
  case Kind::Choice:
    return lower(t);
  case Kind::Word:
    return std::string(s.name) == "gimp_bodyK_file" ? contentHash(t) : t;
  }
  return t;
}

struct Given {
  std::string value, text; // canonical, as given
};

/// A record's lines by option name.
std::map<std::string, Given> parse(const std::string &record) {
  std::map<std::string, Given> m;
  std::istringstream in(record);
  std::string line;
  while (std::getline(in, line)) {
    const size_t a = line.find('\t'), b = a == std::string::npos ? a : line.find('\t', a + 1);
    if (b != std::string::npos)
      m[line.substr(0, a)] = {line.substr(a + 1, b - a - 1), line.substr(b + 1)};
  }
  return m;
}

/// The order of the option table, then the name.
std::tuple<size_t, std::string> orderOf(const std::string &name) {
  const OptionSpec *s = findOption(name);
  return {s ? static_cast<size_t>(s - optionTable().data()) : optionTable().size(), name};
}

} // namespace

bool keptAcrossRestart(const std::string &name) {
  const OptionSpec *s = findOption(name);
  return !s || kKept.count(s->name) > 0;
}

std::string sceneRecord() {
  char *all = nullptr;
  if (PetscOptionsGetAll(nullptr, &all) || !all) return "";
  std::istringstream in(all);
  std::set<std::string> names;
  for (std::string tok; in >> tok;)
    if (tok.rfind("-gimp_", 0) == 0 && !keptAcrossRestart(tok.substr(1)))
      names.insert(tok.substr(1));
  (void)PetscFree(all);
  std::vector<std::string> sorted(names.begin(), names.end());
  std::sort(sorted.begin(), sorted.end(),
            [](const std::string &a, const std::string &b) { return orderOf(a) < orderOf(b); });
  std::string record;
  for (const std::string &name : sorted) {
    const char *value = nullptr; // (the whole value: a polygon may be long)
    PetscBool set = PETSC_FALSE;
    if (PetscOptionsFindPair(nullptr, nullptr, ("-" + name).c_str(), &value, &set) || !set)
      continue;
    const std::string text = value ? value : "";
    record += name + "\t" + canonical(*findOption(name), text) + "\t" + trim(text) + "\n";
  }
  return record;
}

std::string sceneDifference(const std::string &stored, const std::string &current,
                            const std::string &file) {
  const std::map<std::string, Given> was = parse(stored), is = parse(current);
  std::set<std::string> names;
  for (const auto &m : {was, is})
    for (const auto &kv : m)
      names.insert(kv.first);
  std::vector<std::string> sorted(names.begin(), names.end());
  std::sort(sorted.begin(), sorted.end(),
            [](const std::string &a, const std::string &b) { return orderOf(a) < orderOf(b); });
  const std::string tail = "; a restart must use the scene it was written with";
  for (const std::string &name : sorted) {
    const OptionSpec *s = findOption(name);
    if (!s) continue;
    const std::string def = canonical(*s, s->def);
    const auto w = was.find(name), i = is.find(name);
    const std::string wv = w == was.end() ? def : w->second.value,
                      iv = i == is.end() ? def : i->second.value;
    if (wv == iv) continue;
    const std::string opt = "option -" + name + " ",
                      what = "the checkpoint " + file + " was written ";
    const bool plainDefault = s->def[0] != '\0' && s->def[0] != '(';
    if (i == is.end())
      return opt + (plainDefault ? std::string(s->def) + " (the default)" : "(not given)") + ": " +
             what + "with -" + name + " " + w->second.text + tail;
    if (w == was.end())
      return opt + i->second.text + ": " + what + "without it" +
             (plainDefault ? " (the default " + std::string(s->def) + ")" : "") + tail;
    return opt + i->second.text + ": " + what + "with -" + name + " " + w->second.text +
           (w->second.text == i->second.text ? " (another content)" : "") + tail;
  }
  return "";
}

} // namespace gimp::input
