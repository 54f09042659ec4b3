#pragma once
// The peak of a square pyramid located in a cloud (paper 004, section 5:
// "we use a pyramid for a target because it is possible to locate the peak
// of the pyramid in the range image"). Instead of a cursor: the points
// above the table are split by face (the dominant horizontal direction from
// the current apex estimate; faces facing +-x and +-y), a plane is fitted to
// each face (outliers trimmed) and the apex is the least-squares meeting
// point of the four planes; again, each time splitting about the new apex.

#include <optional>
#include <vector>

#include <Eigen/Core>

namespace ephor::stripe {

struct PyramidApexOptions {
  double min_height_mm = 4.0;    // ignore points this near the table (the base and the table)
  double ridge_margin_mm = 3.0;  // ignore points this near a ridge (| |dx| - |dy| | small)
  size_t min_face_points = 20;   // a face with fewer points gives no plane
  int iterations = 3;
  // Per face, points beyond max(3 sigma, min_trim_mm) of its plane are
  // dropped and the plane fitted again, up to trim_rounds times.
  int trim_rounds = 3;
  double min_trim_mm = 0.3;
  // A face whose points spread less than this (1 sigma, mm) across their
  // main direction is left out.
  double min_face_spread_mm = 6.0;
};

struct PyramidApex {
  Eigen::Vector3d apex_mm;  // table frame
  double face_rms_mm[4];    // 1 sigma of each face's plane fit (+x, -x, +y, -y)
  size_t face_points[4];

  // Faces with fewer than min_face_points points are left out (face_rms 0);
  // nullopt when fewer than three faces remain or the planes do not meet in
  // a point.
  static std::optional<PyramidApex> locate(const std::vector<Eigen::Vector3d>& cloud,
                                           const Eigen::Vector3d& initial_apex_mm,
                                           const PyramidApexOptions& options = {});
};

}  // namespace ephor::stripe
