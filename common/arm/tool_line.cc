#include "common/arm/tool_line.h"

#include <algorithm>

namespace ephor::arm {

ToolLine::ToolLine(const Eigen::Isometry3d& from, const Eigen::Isometry3d& to)
    : p0_(from.translation()), p1_(to.translation()), r0_(from.linear()), r1_(to.linear()) {
  r0_.normalize();
  r1_.normalize();
  length_mm_ = (p1_ - p0_).norm();
  angle_rad_ = r0_.angularDistance(r1_);
}

Eigen::Isometry3d ToolLine::at(double u) const {
  u = std::clamp(u, 0.0, 1.0);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = r0_.slerp(u, r1_).toRotationMatrix();
  t.translation() = p0_ + u * (p1_ - p0_);
  return t;
}

std::optional<LineBreak> ToolLine::follow(const Puma560& arm, const Joints& start, int samples,
                                          double max_jump_rad,
                                          const std::function<bool(const Joints&)>& accept,
                                          Joints* end) const {
  const int n = std::max(1, samples);
  Joints q = start;
  std::optional<LineBreak> stop;
  for (int i = 1; i <= n && !stop; ++i) {
    const double u = static_cast<double>(i) / n;
    const auto next = arm.nearest_inverse(at(u), q);
    if (!next) {
      stop = LineBreak{LineBreak::Kind::kUnreachable, u, 0.0};
      break;
    }
    const double jump = (*next - q).cwiseAbs().maxCoeff();
    if (jump > max_jump_rad) {
      stop = LineBreak{LineBreak::Kind::kJump, u, jump};
      break;
    }
    if (accept && !accept(*next)) stop = LineBreak{LineBreak::Kind::kRejected, u, 0.0};
    q = *next;
  }
  if (end != nullptr) *end = q;
  return stop;
}

}  // namespace ephor::arm
