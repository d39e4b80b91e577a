#pragma once
// JSON for every tool report and results file, built with nlohmann-json (Debian
// nlohmann-json3-dev). Callers fill an io::Json (keys keep insertion order) and print it with
// json_line / json_lines, which keep the established layout ("key": value, ", " between
// members) that tests and scripts grep for; number text and string escaping are nlohmann's
// (shortest round-trip doubles, integers exact), except that a whole double below 2^53 prints
// without ".0" ("fps": 1), as the tools' printf output always did.
//
// Non-finite numbers never reach the output: JSON has no NaN/Inf, and nlohmann would print
// them as null silently. A value that may legitimately be undefined (a PSNR of identical
// images, an fps without wall time) is passed through finite_or_null(), which states that at
// the call site; any other NaN/Inf makes the writers throw JsonNonFiniteError naming the member
// (e.g. "/ate/rmse"), so the command fails with a clear message instead of lying.
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>

namespace vigs::io {

using Json = nlohmann::ordered_json;

class JsonNonFiniteError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The number, or JSON null when it is NaN or infinite (an explicit "not defined").
Json finite_or_null(double v);
/// The number, or JSON null when absent or not finite.
Json finite_or_null(const std::optional<double>& v);

/// `v` rounded to `digits` significant decimal digits (printf %.*g), for reports whose
/// precision is part of their format (`vigs align` prints 9 digits). Non-finite values pass
/// through unchanged, so the writers still refuse them.
Json rounded(double v, int digits);
/// `v` rounded to `decimals` places (printf %.*f); non-finite values pass through unchanged.
Json fixed(double v, int decimals);

/// One line: {"a": 1, "b": [1, 2], "c": {"d": "x"}}. Throws JsonNonFiniteError.
std::string json_line(const Json& j);

/// The top-level members one per line, each value on one line, except that a top-level array
/// of objects (or an empty one) has one object per line:
///   {
///     "a": 1,
///     "b": {"c": 2},
///     "c": [
///       {"d": 1},
///       {"d": 2}
///     ]
///   }
/// A non-object is printed as json_line. Throws JsonNonFiniteError.
std::string json_lines(const Json& j);

/// Throws JsonNonFiniteError naming the first NaN/Inf member (JSON pointer), else returns.
void require_finite(const Json& j);

}  // namespace vigs::io
