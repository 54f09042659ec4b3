#include "common/shepherd/worldmodel/associator.h"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace ephor::worldmodel {
namespace {

// Distance from a blob to the path from where a hidden object was last seen
// to where it is reckoned now.
double path_distance_px(const GatedPrediction& p, const Eigen::Vector2d& blob_px) {
  const Eigen::Vector2d path = p.predicted_px - p.last_seen_px;
  const double length_sq = path.squaredNorm();
  const double along = length_sq > 0.0
                           ? std::clamp((blob_px - p.last_seen_px).dot(path) / length_sq, 0.0, 1.0)
                           : 0.0;
  return (blob_px - (p.last_seen_px + along * path)).norm();
}

// The prior cost of "it stopped or turned back" against "it kept walking":
// even odds (ln 2). Enough that two sheep crossing under one merged blob,
// whose paths overlap, still come out on the side they were walking to.
constexpr double kOffPredictionCost = 0.6931471805599453;

}  // namespace

std::vector<Assignment> Associator::assign(const std::vector<GatedPrediction>& objects,
                                           const std::vector<Eigen::Vector2d>& blobs_px,
                                           const std::vector<bool>& blob_taken) {
  struct Candidate {
    double score;  // negative log-likelihood, see the header
    size_t object;
    size_t blob;
    double distance;
  };
  std::vector<Candidate> candidates;
  for (size_t o = 0; o < objects.size(); ++o) {
    const double gate = objects[o].gate_px;
    if (!(gate > 0.0) || !objects[o].predicted_px.allFinite()) continue;
    const double sigma = gate / 3.0;  // px
    const bool has_path = objects[o].last_seen_px.allFinite();
    for (size_t b = 0; b < blobs_px.size(); ++b) {
      if (b < blob_taken.size() && blob_taken[b]) continue;
      double d = (blobs_px[b] - objects[o].predicted_px).norm();
      double cost = d * d / (2.0 * sigma * sigma);
      if (has_path) {
        const double on_path = path_distance_px(objects[o], blobs_px[b]);
        const double path_cost = on_path * on_path / (2.0 * sigma * sigma) + kOffPredictionCost;
        if (path_cost < cost) {
          cost = path_cost;
          d = on_path;
        }
      }
      if (d <= gate) candidates.push_back({cost + 2.0 * std::log(sigma), o, b, d});
    }
  }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    return std::tie(a.score, a.object, a.blob) < std::tie(b.score, b.object, b.blob);
  });
  std::vector<bool> object_done(objects.size(), false);
  std::vector<bool> blob_done(blobs_px.size(), false);
  std::vector<Assignment> out;
  for (const Candidate& c : candidates) {
    if (object_done[c.object] || blob_done[c.blob]) continue;
    object_done[c.object] = true;
    blob_done[c.blob] = true;
    out.push_back({c.object, c.blob, c.distance});
  }
  return out;
}

}  // namespace ephor::worldmodel
