#pragma once
// Associator: gated nearest-neighbour assignment of blobs to objects, the
// matching step shared by stages 1 and 2 of paper 003, section 4.2. Each
// object offers a predicted image position and a gate radius; every pair
// closer than the gate is a candidate, and candidates are taken in order of
// distance / gate (best first), each object and blob at most once. Sorting by
// the gate-normalised distance is the paper's "the allowed percent is
// increased until a positive match is found": the tightest relative match
// wins first.
//
// Units: px, image frame. Pure, deterministic (ties break by index).

#include <cstddef>
#include <vector>

#include <Eigen/Core>

namespace ephor::worldmodel {

struct GatedPrediction {
  Eigen::Vector2d predicted_px;  // where the object should be now, px
  double gate_px = 0.0;          // accept blobs within this distance, px
};

struct Assignment {
  size_t object = 0;  // index into the predictions
  size_t blob = 0;    // index into the blobs
  double distance_px = 0.0;
};

class Associator {
 public:
  // Blobs with blob_taken[i] true (if given) are not offered.
  static std::vector<Assignment> assign(const std::vector<GatedPrediction>& objects,
                                        const std::vector<Eigen::Vector2d>& blobs_px,
                                        const std::vector<bool>& blob_taken = {});
};

}  // namespace ephor::worldmodel
