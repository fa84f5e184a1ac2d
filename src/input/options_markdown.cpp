// The option table and the feature table as Markdown: the lists of docs/options.md, which a test
// compares with `gimp -gimp_options_markdown`.
#include "gimp/input/options.hpp"

#include <sstream>

namespace gimp::input {

namespace {

const char *dimsText(Dims d) {
  return d == In2D ? "2D" : d == In3D ? "3D" : "2D, 3D";
}

/// What an option's value is, with its check ("a number > 0", "x0,y0,x1,y1 (2D), ...").
std::string valuesText(const OptionSpec &s) {
  const Check &k = s.check;
  std::string range = k.rule(); // "must be > 0" -> " > 0", "must lie in [0, 1)" -> " in [0, 1)"
  if (k.op == Check::Within && k.integer)
    range = " from " + formatNumber(k.lo) + " to " + formatNumber(k.hi);
  else if (!range.empty())
    range = " " + range.substr(range.find(' ', 5) + 1);
  switch (s.kind) {
  case Kind::Real:
    return "number" + range;
  case Kind::Int:
    return "integer" + range;
  case Kind::Bool:
    return "true, false";
  case Kind::Word:
    return "word";
  case Kind::Choice: {
    std::string out, choices = s.valuesIn2D;
    size_t at = 0;
    while (at <= choices.size()) {
      const size_t next = std::min(choices.find('|', at), choices.size());
      const std::string c = choices.substr(at, next - at);
      const Dims d = dimsOf(s.name, c);
      out += (out.empty() ? "" : ", ") + c +
             (d == InBoth ? "" : std::string(" (") + dimsText(d) + ")");
      at = next + 1;
    }
    return out;
  }
  case Kind::Reals:
  case Kind::Ramp:
    if (!s.valuesIn3D || std::string(s.valuesIn3D) == s.valuesIn2D) return s.valuesIn2D;
    return std::string(s.valuesIn2D) + " (2D); " + s.valuesIn3D + " (3D)";
  }
  return "";
}

std::string cell(std::string s) {
  std::string r;
  for (char c : s)
    r += c == '|' ? std::string("\\|") : std::string(1, c);
  return r;
}

} // namespace

std::string optionsMarkdown() {
  std::ostringstream o;
  o << "| option | dims | values | default | unit | what |\n| --- | --- | --- | --- | --- | --- "
       "|\n";
  for (const OptionSpec &s : optionTable())
    o << "| `-" << s.name << "` | " << dimsText(dimsOf(s.name)) << " | " << cell(valuesText(s))
      << " | " << cell(s.def) << " | " << cell(s.unit) << " | " << cell(s.help) << " |\n";
  o << "\nWhat exists in one dimension only (every refusal of an option in the other dimension "
       "names its line):\n\n| feature | dims | options | why |\n| --- | --- | --- | --- |\n";
  for (const Feature &f : featureTable()) {
    std::string opts;
    for (const char *n : f.options)
      opts += (opts.empty() ? "" : ", ") + std::string("`-") + n + "`";
    o << "| " << f.what << " | " << dimsText(f.dims) << " | " << opts << " | " << cell(f.why)
      << " |\n";
  }
  return o.str();
}

} // namespace gimp::input
