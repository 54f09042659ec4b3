#include "common/shepherd/calibrate/tool_spot_finder.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace ephor::calibrate {

namespace {

struct Component {
  double area = 0.0;
  double su = 0.0, sv = 0.0;  // sums of pixel coordinates, px
  double peak = 0.0;
  Eigen::Vector2d centre() const { return {su / area, sv / area}; }
};

}  // namespace

ToolSpotFinder::ToolSpotFinder(ToolSpotFinderConfig config) : config_(config) {
  const auto& c = config_;
  if (!std::isfinite(c.min_contrast) || c.min_contrast <= 0.0 || !std::isfinite(c.min_area_px) ||
      !std::isfinite(c.max_area_px) || c.min_area_px < 1.0 || c.max_area_px < c.min_area_px ||
      !std::isfinite(c.window_margin_px) || c.window_margin_px < 0.0 || !std::isfinite(c.gate_px) ||
      c.gate_px <= 0.0)
    throw std::invalid_argument(
        "ToolSpotFinder: min_contrast > 0, 1 <= min_area_px <= max_area_px, window_margin_px >= "
        "0 and gate_px > 0, all finite");
}

SpotResult ToolSpotFinder::find(const GreyFrame& lit, const GreyFrame& dark,
                                const std::optional<Eigen::Vector2d>& expected_px) const {
  const int w = lit.width, h = lit.height;
  if (w <= 0 || h <= 0 || lit.data.size() != static_cast<size_t>(w) * static_cast<size_t>(h))
    return {std::nullopt, "lit frame: size does not match width x height"};
  if (dark.width != w || dark.height != h || dark.data.size() != lit.data.size())
    return {std::nullopt, "lit and dark frames differ in size"};
  if (expected_px && !expected_px->allFinite())
    return {std::nullopt, "expected position is not finite"};

  const size_t n = lit.data.size();
  std::vector<float> diff(n);
  for (size_t i = 0; i < n; ++i)
    diff[i] = static_cast<float>(lit.data[i]) - static_cast<float>(dark.data[i]);

  // 4-connected components of the pixels that brightened by more than min_contrast.
  const float thr = static_cast<float>(config_.min_contrast);
  std::vector<uint8_t> seen(n, 0);
  std::vector<Component> accepted;
  int too_small = 0, too_large = 0, outside_gate = 0;
  std::vector<int> stack;
  for (size_t start = 0; start < n; ++start) {
    if (seen[start] || diff[start] <= thr) continue;
    Component c;
    stack.assign(1, static_cast<int>(start));
    seen[start] = 1;
    while (!stack.empty()) {
      const int i = stack.back();
      stack.pop_back();
      const int u = i % w, v = i / w;
      c.area += 1.0;
      c.su += u;
      c.sv += v;
      c.peak = std::max(c.peak, static_cast<double>(diff[static_cast<size_t>(i)]));
      const int nb[4] = {u > 0 ? i - 1 : -1, u + 1 < w ? i + 1 : -1, v > 0 ? i - w : -1,
                         v + 1 < h ? i + w : -1};
      for (int j : nb) {
        if (j < 0 || seen[static_cast<size_t>(j)] || diff[static_cast<size_t>(j)] <= thr) continue;
        seen[static_cast<size_t>(j)] = 1;
        stack.push_back(j);
      }
    }
    if (c.area < config_.min_area_px) {
      ++too_small;
    } else if (c.area > config_.max_area_px) {
      ++too_large;
    } else if (expected_px && (c.centre() - *expected_px).norm() > config_.gate_px) {
      ++outside_gate;
    } else {
      accepted.push_back(c);
    }
  }
  if (accepted.empty()) {
    std::string why = fmt::format(
        "no light spot: no component of {:.0f}..{:.0f} px brightening by more than {:.0f} grey "
        "levels",
        config_.min_area_px, config_.max_area_px, config_.min_contrast);
    if (expected_px)
      why += fmt::format(" within {:.0f} px of ({:.1f}, {:.1f})", config_.gate_px, expected_px->x(),
                         expected_px->y());
    why += fmt::format(" ({} too small, {} too large, {} outside the gate)", too_small, too_large,
                       outside_gate);
    return {std::nullopt, why};
  }
  if (accepted.size() > 1) {
    std::string why = fmt::format("ambiguous: {} candidate spots", accepted.size());
    for (const auto& c : accepted)
      why += fmt::format(" ({:.1f}, {:.1f})", c.centre().x(), c.centre().y());
    why += " (something else changed between the lit and the dark frame)";
    return {std::nullopt, why};
  }

  // Sub-pixel centre: signed difference-weighted centroid over a disc.
  const Component& c = accepted.front();
  const Eigen::Vector2d c0 = c.centre();
  const double r = std::sqrt(c.area / M_PI) + config_.window_margin_px;
  const int u0 = std::max(0, static_cast<int>(std::floor(c0.x() - r)));
  const int u1 = std::min(w - 1, static_cast<int>(std::ceil(c0.x() + r)));
  const int v0 = std::max(0, static_cast<int>(std::floor(c0.y() - r)));
  const int v1 = std::min(h - 1, static_cast<int>(std::ceil(c0.y() + r)));
  double sw = 0.0, su = 0.0, sv = 0.0;
  for (int v = v0; v <= v1; ++v)
    for (int u = u0; u <= u1; ++u) {
      if (Eigen::Vector2d(u - c0.x(), v - c0.y()).squaredNorm() > r * r) continue;
      const double d =
          diff[static_cast<size_t>(v) * static_cast<size_t>(w) + static_cast<size_t>(u)];
      sw += d;
      su += d * u;
      sv += d * v;
    }
  if (!(sw > 0.0)) return {std::nullopt, "light spot has no positive weight"};
  const Eigen::Vector2d centre(su / sw, sv / sw);
  if ((centre - c0).norm() > r) return {std::nullopt, "light spot centroid left its window"};
  if (c0.x() - r < 0.0 || c0.y() - r < 0.0 || c0.x() + r > w - 1 || c0.y() + r > h - 1)
    return {std::nullopt,
            fmt::format("light spot at ({:.1f}, {:.1f}) is cut by the image edge", c0.x(), c0.y())};
  return {ToolSpot{centre, c.area, c.peak}, ""};
}

}  // namespace ephor::calibrate
