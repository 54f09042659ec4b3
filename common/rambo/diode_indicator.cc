#include "common/rambo/diode_indicator.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ephor::rambo {

DiodeIndicator::DiodeIndicator(std::vector<Diode> diodes, double acceptance_deg,
                               double lens_radius_mm, double required_s)
    : diodes_(std::move(diodes)),
      acceptance_deg_(acceptance_deg),
      lens_radius_mm_(lens_radius_mm),
      required_s_(required_s),
      readings_(diodes_.size()),
      tagged_at_s_(diodes_.size(), -1.0) {
  if (!(acceptance_deg > 0.0 && acceptance_deg < 90.0))
    throw std::invalid_argument("diode acceptance angle must be in (0, 90) deg");
  if (!(lens_radius_mm > 0.0) || !std::isfinite(lens_radius_mm))
    throw std::invalid_argument("lens radius must be positive and finite");
  if (!(required_s > 0.0) || !std::isfinite(required_s))
    throw std::invalid_argument("required lit duration must be positive and finite");
}

DiodeReading DiodeIndicator::read(int i, const Eigen::Isometry3d& target_in_base,
                                  const Eigen::Vector3d& beam_origin_mm,
                                  const Eigen::Vector3d& beam_dir) const {
  const Diode& d = diodes_.at(static_cast<std::size_t>(i));
  DiodeReading r;
  const Eigen::Vector3d lens = target_in_base * d.lens_mm;
  const Eigen::Vector3d inward = -(target_in_base.linear() * d.axis);
  const Eigen::Vector3d dir = beam_dir.normalized();
  r.beam_angle_deg = std::acos(std::clamp(dir.dot(inward), -1.0, 1.0)) * 180.0 / M_PI;
  const Eigen::Vector3d to_lens = lens - beam_origin_mm;
  const double along = to_lens.dot(dir);
  r.beam_offset_mm = along > 0.0 ? (to_lens - along * dir).norm() : 1e9;
  r.lit = r.beam_angle_deg <= acceptance_deg_ && r.beam_offset_mm <= lens_radius_mm_;
  return r;
}

void DiodeIndicator::step(double t_s, const Eigen::Isometry3d& target_in_base,
                          const Eigen::Vector3d& beam_origin_mm, const Eigen::Vector3d& beam_dir) {
  const bool beam_ok = beam_origin_mm.allFinite() && beam_dir.allFinite() &&
                       beam_dir.norm() > 1e-9 && target_in_base.matrix().allFinite();
  int lit = -1;
  for (int i = 0; i < size(); ++i) {
    readings_[static_cast<std::size_t>(i)] =
        beam_ok ? read(i, target_in_base, beam_origin_mm, beam_dir) : DiodeReading{};
    if (readings_[static_cast<std::size_t>(i)].lit && lit < 0) lit = i;
  }
  if (lit != lit_) {
    lit_ = lit;
    lit_since_s_ = t_s;
  }
  lit_s_ = lit_ >= 0 ? t_s - lit_since_s_ : 0.0;
  if (lit_ >= 0 && lit_s_ >= required_s_ && !tagged(lit_))
    tagged_at_s_[static_cast<std::size_t>(lit_)] = t_s;
}

void DiodeIndicator::reset_tags(double t_s) {
  std::fill(tagged_at_s_.begin(), tagged_at_s_.end(), -1.0);
  lit_since_s_ = t_s;
  lit_s_ = 0.0;
}

int DiodeIndicator::tagged_count() const {
  int n = 0;
  for (double t : tagged_at_s_) n += t >= 0.0 ? 1 : 0;
  return n;
}

}  // namespace ephor::rambo
