#include "common/shepherd/worldmodel/associator.h"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace ephor::worldmodel {

std::vector<Assignment> Associator::assign(const std::vector<GatedPrediction>& objects,
                                           const std::vector<Eigen::Vector2d>& blobs_px,
                                           const std::vector<bool>& blob_taken) {
  struct Candidate {
    double score;  // distance / gate
    size_t object;
    size_t blob;
    double distance;
  };
  std::vector<Candidate> candidates;
  for (size_t o = 0; o < objects.size(); ++o) {
    const double gate = objects[o].gate_px;
    if (!(gate > 0.0) || !objects[o].predicted_px.allFinite()) continue;
    for (size_t b = 0; b < blobs_px.size(); ++b) {
      if (b < blob_taken.size() && blob_taken[b]) continue;
      const double d = (blobs_px[b] - objects[o].predicted_px).norm();
      if (d <= gate) candidates.push_back({d / gate, o, b, d});
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
