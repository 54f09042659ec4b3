#include "procs/shepherd/planner/recorded_start.h"

#include <cmath>
#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace ephor::planner {

namespace {

double finite_number(const nlohmann::json& sheep, const char* key, int id) {
  const auto it = sheep.find(key);
  if (it == sheep.end() || !it->is_number() || !std::isfinite(it->get<double>()))
    throw std::invalid_argument("GROUND_TRUTH sheep " + std::to_string(id) + ": " + key +
                                " is missing, not a number or not finite");
  return it->get<double>();
}

}  // namespace

std::vector<Sheep> sheep_from_ground_truth_row(const std::string& json_line) {
  const auto row = nlohmann::json::parse(json_line, nullptr, false);
  if (row.is_discarded() || !row.is_object())
    throw std::invalid_argument("not a JSON object (want a row of tools/ephor log export --json)");
  const auto msg = row.find("msg");
  if (msg == row.end() || !msg->is_object() || !msg->contains("sheep") ||
      !(*msg)["sheep"].is_array())
    throw std::invalid_argument("no msg.sheep array: not a GROUND_TRUTH row");
  std::vector<Sheep> out;
  for (const auto& s : (*msg)["sheep"]) {
    if (!s.is_object()) throw std::invalid_argument("a GROUND_TRUTH sheep is not an object");
    const int id = s.contains("id") && s["id"].is_number_integer() ? s["id"].get<int>() : -1;
    if (s.contains("on_field") && s["on_field"].is_boolean() && !s["on_field"].get<bool>())
      continue;
    Sheep sheep;
    sheep.id = id;
    sheep.x_mm = finite_number(s, "x_mm", id);
    sheep.y_mm = finite_number(s, "y_mm", id);
    const double heading = finite_number(s, "heading_rad", id);
    const double speed = finite_number(s, "speed_mm_s", id);
    sheep.vx_mm_s = speed * std::cos(heading);
    sheep.vy_mm_s = speed * std::sin(heading);
    out.push_back(sheep);
  }
  if (out.empty()) throw std::invalid_argument("no sheep on the field in the GROUND_TRUTH row");
  return out;
}

std::vector<Sheep> sheep_from_ground_truth_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument("cannot read " + path);
  std::string line;
  if (!std::getline(in, line)) throw std::invalid_argument(path + " is empty");
  try {
    return sheep_from_ground_truth_row(line);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(path + ", first line: " + e.what());
  }
}

}  // namespace ephor::planner
