#pragma once
// CLI11's Range and PositiveNumber compare with < and >, which NaN passes (`--seconds nan`
// ran the whole route). Every floating-point option of `vigs` adds this check: the value must
// parse whole as a finite number.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdlib>
#include <string>

namespace vigs::apps {

inline const CLI::Validator kFiniteNumber(
    [](std::string& text) -> std::string {
      char* end = nullptr;
      const double v = std::strtod(text.c_str(), &end);
      if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v))
        return "'" + text + "' is not a finite number";
      return {};
    },
    "FINITE", "finite number");

}  // namespace vigs::apps
