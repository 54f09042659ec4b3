#pragma once
// The target's diodes and indicator electronics (RAMBO paper, section 7): each
// diode sits at the focus of a lens closing a tube, so it fires only while the
// laser beam is roughly aligned with the lens's optical axis and enters the
// lens; success is signalled once a diode has been lit for the required
// duration without a break. Pure code: the simulator steps it.
//
// Beam: a ray from the laser's exit (base frame, mm) along a unit direction.
// Diode i is lit when the ray passes within lens_radius_mm of the lens centre
// (the centre lies ahead of the exit) and the angle between the beam and the
// inward axis (-axis) is within acceptance_deg.
#include <cstdint>
#include <vector>

#include <Eigen/Geometry>

#include "common/rambo/rambo_cell.h"

namespace ephor::rambo {

struct DiodeReading {
  bool lit = false;
  double beam_angle_deg = 180.0;  // beam against the inward axis
  double beam_offset_mm = 1e9;    // ray's distance from the lens centre (inf-like behind the exit)
};

class DiodeIndicator {
 public:
  // Throws std::invalid_argument for a non-positive acceptance, radius or duration.
  DiodeIndicator(std::vector<Diode> diodes, double acceptance_deg, double lens_radius_mm,
                 double required_s);

  // One diode against the beam (target pose in base, mm).
  DiodeReading read(int i, const Eigen::Isometry3d& target_in_base,
                    const Eigen::Vector3d& beam_origin_mm, const Eigen::Vector3d& beam_dir) const;

  // Advances the electronics to t_s (s, increasing) with the beam as it is now.
  // Non-finite input counts as no beam.
  void step(double t_s, const Eigen::Isometry3d& target_in_base,
            const Eigen::Vector3d& beam_origin_mm, const Eigen::Vector3d& beam_dir);

  // Every diode untagged again (the demo's next round): a diode lit now
  // must stay lit the required duration from here to be tagged again.
  void reset_tags(double t_s);

  int size() const { return static_cast<int>(diodes_.size()); }
  int lit_diode() const { return lit_; }   // -1 = none
  double lit_s() const { return lit_s_; }  // unbroken, s
  bool tagged(int i) const { return tagged_at_s_[static_cast<std::size_t>(i)] >= 0.0; }
  double tagged_at_s(int i) const { return tagged_at_s_[static_cast<std::size_t>(i)]; }  // -1 = not
  int tagged_count() const;
  const std::vector<DiodeReading>& readings() const { return readings_; }
  double acceptance_deg() const { return acceptance_deg_; }
  double lens_radius_mm() const { return lens_radius_mm_; }
  double required_s() const { return required_s_; }

 private:
  std::vector<Diode> diodes_;
  double acceptance_deg_, lens_radius_mm_, required_s_;
  std::vector<DiodeReading> readings_;
  std::vector<double> tagged_at_s_;
  int lit_ = -1;
  double lit_since_s_ = 0.0, lit_s_ = 0.0;
};

}  // namespace ephor::rambo
