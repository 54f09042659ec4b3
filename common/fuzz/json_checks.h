#pragma once
// Checks on JSON that a fuzz target's process writes for a page or a file
// (issue 18): nlohmann writes NaN and infinities as null, which a page's
// code then reads as 0 or breaks on, so a page's state should carry none.

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

namespace ephor::fuzz {

// The path (e.g. "/sched/0/utilisation") of the first number in `j` that is
// NaN or infinite, or "" when every number is finite.
inline std::string first_non_finite(const nlohmann::json& j, const std::string& path = "") {
  if (j.is_number_float()) return std::isfinite(j.get<double>()) ? "" : (path.empty() ? "/" : path);
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it)
      if (auto p = first_non_finite(it.value(), path + "/" + it.key()); !p.empty()) return p;
  } else if (j.is_array()) {
    for (size_t i = 0; i < j.size(); ++i)
      if (auto p = first_non_finite(j[i], path + "/" + std::to_string(i)); !p.empty()) return p;
  }
  return "";
}

}  // namespace ephor::fuzz
