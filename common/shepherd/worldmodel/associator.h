#pragma once
// Associator: gated nearest-neighbour assignment of blobs to objects, the
// matching step shared by stages 1 and 2 of paper 003, section 4.2. Each
// object offers a predicted image position and a gate radius; every pair
// closer than the gate is a candidate, and candidates are taken best first,
// each object and blob at most once.
//
// "Best" is the negative log-likelihood of the blob under a circular
// Gaussian around the prediction whose 3 sigma is the gate: d^2 / (2 s^2) +
// 2 ln s. Among objects with equal gates (stage 1) that is nearest first, as
// the paper's "the allowed percent is increased until a positive match is
// found". Where gates differ (stage 2: the gate grows with the time an object
// has been hidden) it no longer lets an object hidden for seconds, whose
// wide gate makes any blob look relatively close, take the blob of one hidden
// a frame ago a few px from its prediction (issue 13: a sheep nudged by the
// arm lost its id to one hidden 12 s, 55 px away).
//
// Units: px, image frame. Pure, deterministic (ties break by index).

#include <cstddef>
#include <limits>
#include <vector>

#include <Eigen/Core>

namespace ephor::worldmodel {

struct GatedPrediction {
  Eigen::Vector2d predicted_px;  // where the object should be now, px
  double gate_px = 0.0;          // accept blobs within this distance, px
  // Where a hidden object was last seen, px, or NaN. When given, the object
  // may also have stopped or turned anywhere on the path from here to
  // predicted_px (at even odds against having kept walking), and a blob may
  // match that path: a sheep hidden under the lowered tool is usually being
  // turned round, so dead-reckoning it on at its old velocity alone puts it on
  // the wrong side (issue 13, recorded runs with clouds).
  Eigen::Vector2d last_seen_px{std::numeric_limits<double>::quiet_NaN(),
                               std::numeric_limits<double>::quiet_NaN()};
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
