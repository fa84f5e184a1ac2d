// Values as summary.json writes them (strict JSON).
#pragma once

#include <string>

namespace gimp {

/// A number: NaN and inf are not JSON, they are written as null.
std::string jsonNumber(double v);
/// A string: quotes, backslashes and control characters escaped, bytes that are not UTF-8
/// replaced by U+FFFD.
std::string jsonString(const std::string &s);

} // namespace gimp
