#include "common/shepherd/worldmodel/world_model.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "common/shepherd/worldmodel/associator.h"

namespace ephor::worldmodel {
namespace {

bool finite_positive(double v) { return std::isfinite(v) && v > 0.0; }
bool finite_nonneg(double v) { return std::isfinite(v) && v >= 0.0; }

// t1_us - t0_us in s, for capture utimes (us). In double: the int64_t
// difference of two utimes far apart (a sender's garbage, e.g. a first frame
// at -9.2e18 us and the next at 1.7e15 us) overflows (fuzz target
// shepherd_world_model). Exact, as the integer difference was, for utimes
// within 2^53 us (285 years) of 0.
double seconds_between(int64_t t0_us, int64_t t1_us) {
  return (static_cast<double>(t1_us) - static_cast<double>(t0_us)) * 1e-6;
}

}  // namespace

WorldModel::WorldModel(calibration::FieldCalibration calibration, WorldModelConfig config)
    : calibration_(std::move(calibration)), config_(std::move(config)) {
  const auto& c = config_;
  if (!finite_positive(c.visible_gate_px) || !finite_nonneg(c.visible_gate_growth_px_s) ||
      !finite_positive(c.obscured_gate_px) || !finite_nonneg(c.obscured_gate_growth_px_s) ||
      !(c.obscured_gate_max_px >= c.obscured_gate_px) || !(c.merge_area_ratio > 1.0) ||
      !finite_positive(c.max_obscured_s) || !finite_nonneg(c.report_dead_s) ||
      !finite_nonneg(c.dead_reckon_max_s) || !finite_nonneg(c.hidden_escape_margin_mm) ||
      !finite_nonneg(c.visible_escape_margin_mm) ||
      !(c.partial_area_ratio >= 0.0 && c.partial_area_ratio < 1.0) ||
      !(c.reacquire_area_ratio >= c.partial_area_ratio && c.reacquire_area_ratio < 1.0) ||
      !std::isfinite(c.mark_height_mm) || !finite_nonneg(c.mark_diameter_mm))
    throw std::invalid_argument(
        "world model config: gates, growth rates and times must be finite and positive, "
        "obscured_gate_max_px >= obscured_gate_px, merge_area_ratio > 1, "
        "0 <= partial_area_ratio <= reacquire_area_ratio < 1");
  DoubleAlphaBetaFilter probe(c.filter);  // throws on bad filter parameters
  mark_map_ = calibration_.matrix_at_height(c.mark_height_mm);
  // mm^2 per px^2 near the image centre is |det| of the map's linear part.
  const double mm2_per_px2 = std::abs(mark_map_.block<2, 2>(0, 0).determinant());
  if (c.mark_diameter_mm > 0.0 && mm2_per_px2 > 0.0)
    whole_mark_area_px_ =
        std::numbers::pi * 0.25 * c.mark_diameter_mm * c.mark_diameter_mm / mm2_per_px2;
}

bool WorldModel::inside_field(const Eigen::Vector2d& px, double margin_mm) const {
  const Eigen::Vector2d mm = mark_map_ * px.homogeneous();
  const auto& w = config_.workcell;
  return mm.x() >= -margin_mm && mm.x() <= w.field_length_mm + margin_mm && mm.y() >= -margin_mm &&
         mm.y() <= w.field_width_mm + margin_mm;
}

Eigen::Vector2d WorldModel::dead_reckoned(const Track& t) const {
  return t.seen_px + t.filter.velocity() * std::min(now_s_ - t.seen_s, config_.dead_reckon_max_s);
}

void WorldModel::see(Track& t, const Eigen::Vector2d& z, int area, bool reacquire) {
  if (t.measured && now_s_ > t.last_z_s)
    t.raw_velocity_px_s = (z - t.last_z_px) / (now_s_ - t.last_z_s);
  t.measured = true;
  t.last_z_px = z;
  t.last_z_s = now_s_;
  if (reacquire) {
    // Hidden for a while: the residual to the dead-reckoned position says
    // little about velocity. Keep the velocity; the manoeuvre gate catches a
    // sheep that was turned round while hidden.
    t.filter.relocate(z);
  } else {
    t.filter.update(z);
  }
  t.state = ObjectState::kVisible;
  t.seen_px = t.filter.position();
  t.estimate_px = t.seen_px;
  t.seen_s = now_s_;
  t.area_px = area;
  if (area > t.usual_area_px)
    t.usual_area_px = area;
  else
    t.usual_area_px += 0.05 * (area - t.usual_area_px);
}

bool WorldModel::partly_hidden(const Track& t, int area, double ratio) const {
  return area < ratio * t.usual_area_px;
}

void WorldModel::hide(Track& t) {
  if (t.state != ObjectState::kVisible) return;
  t.state = ObjectState::kObscured;
  // Dead-reckoning starts from the last filtered position and the time it
  // was seen (seen_px / seen_s, already set).
}

std::vector<std::string> WorldModel::take_events() {
  std::vector<std::string> out;
  out.swap(events_);
  return out;
}

void WorldModel::kill(Track& t, const char* why) {
  if (t.state == ObjectState::kDead) return;
  char text[160];
  std::snprintf(text, sizeof text, "object %d dead: %s at (%.0f, %.0f) px, last seen %.1f s ago",
                t.id, why, t.estimate_px.x(), t.estimate_px.y(), now_s_ - t.seen_s);
  events_.emplace_back(text);
  t.state = ObjectState::kDead;
  t.dead_s = now_s_;
  ++counters_.objects_died;
}

WorldModel::FrameResult WorldModel::process(const BlobFrame& frame) {
  if (started_ && frame.utime_us == last_utime_us_) {
    ++counters_.duplicate_frames;
    return FrameResult::kDuplicate;
  }
  if (started_ && frame.utime_us < last_utime_us_) {
    ++counters_.out_of_order_frames;
    return FrameResult::kOutOfOrder;
  }
  if (!started_) {
    started_ = true;
    first_utime_us_ = frame.utime_us;
  }
  const double dt_s = seconds_between(last_utime_us_, frame.utime_us);
  const bool first_frame = counters_.frames == 0;
  last_utime_us_ = frame.utime_us;
  now_s_ = seconds_between(first_utime_us_, frame.utime_us);
  ++counters_.frames;

  std::vector<Eigen::Vector2d> blobs;
  std::vector<int> areas;
  for (const Blob& b : frame.blobs) {
    if (!b.centre_px.allFinite() || b.area_px <= 0) {
      ++counters_.invalid_blobs;
      continue;
    }
    blobs.push_back(b.centre_px);
    areas.push_back(b.area_px);
  }
  std::vector<bool> taken(blobs.size(), false);

  stage1_visible(first_frame ? 0.0 : dt_s, blobs, areas, taken);
  stage2_obscured(blobs, areas, taken);
  stage3_dead_reckon();
  stage4_new(blobs, areas, taken);

  // Forget the long dead.
  for (auto it = tracks_.begin(); it != tracks_.end();) {
    if (it->second.state == ObjectState::kDead &&
        now_s_ - it->second.dead_s > config_.report_dead_s)
      it = tracks_.erase(it);
    else
      ++it;
  }
  return FrameResult::kProcessed;
}

void WorldModel::stage1_visible(double dt_s, const std::vector<Eigen::Vector2d>& blobs,
                                const std::vector<int>& areas, std::vector<bool>& taken) {
  std::vector<Track*> visible;
  std::vector<GatedPrediction> predictions;
  const double gate = config_.visible_gate_px + config_.visible_gate_growth_px_s * dt_s;
  for (auto& [id, t] : tracks_) {
    if (t.state != ObjectState::kVisible) continue;
    t.filter.predict(dt_s);
    visible.push_back(&t);
    predictions.push_back({t.filter.position(), gate});
  }
  const auto matches = Associator::assign(predictions, blobs, taken);
  std::vector<int> blob_of(visible.size(), -1);
  for (const Assignment& m : matches) blob_of[m.object] = static_cast<int>(m.blob);

  // Merged marks: an unmatched object whose prediction lies on a blob already
  // given to another object, when that blob is much larger than the other's
  // usual mark. Neither object can be measured from it: both coast.
  std::vector<bool> coast(visible.size(), false);
  for (size_t o = 0; o < visible.size(); ++o) {
    if (blob_of[o] >= 0) continue;
    for (size_t p = 0; p < visible.size(); ++p) {
      const int b = blob_of[p];
      if (b < 0) continue;
      const double d = (blobs[static_cast<size_t>(b)] - predictions[o].predicted_px).norm();
      const double usual = std::max(1, std::min(visible[o]->area_px, visible[p]->area_px));
      if (d <= gate * 2.0 && areas[static_cast<size_t>(b)] >= config_.merge_area_ratio * usual) {
        coast[o] = true;
        coast[p] = true;
        taken[static_cast<size_t>(b)] = true;  // the merged blob is no new sheep
        ++counters_.merges;
      }
    }
  }

  for (size_t o = 0; o < visible.size(); ++o) {
    Track& t = *visible[o];
    if (coast[o]) {
      hide(t);
      continue;
    }
    if (blob_of[o] < 0) {
      hide(t);  // no consistent blob: obscured (by the arm, usually)
      continue;
    }
    const auto b = static_cast<size_t>(blob_of[o]);
    taken[b] = true;
    if (partly_hidden(t, areas[b], config_.partial_area_ratio)) {
      ++counters_.partial_blobs;
      hide(t);
      continue;
    }
    see(t, blobs[b], areas[b], false);
    if (!inside_field(t.filter.position(), config_.visible_escape_margin_mm)) {
      kill(t, "left the field");  // escaped
    }
  }
}

void WorldModel::stage2_obscured(const std::vector<Eigen::Vector2d>& blobs,
                                 const std::vector<int>& areas, std::vector<bool>& taken) {
  std::vector<Track*> obscured;
  std::vector<GatedPrediction> predictions;
  for (auto& [id, t] : tracks_) {
    if (t.state != ObjectState::kObscured) continue;
    const double hidden_s = now_s_ - t.seen_s;
    const double gate =
        std::min(config_.obscured_gate_max_px,
                 config_.obscured_gate_px + config_.obscured_gate_growth_px_s * hidden_s);
    obscured.push_back(&t);
    predictions.push_back({dead_reckoned(t), gate, t.seen_px});
  }
  // Two coasting objects on one large blob: still merged, keep coasting.
  for (size_t b = 0; b < blobs.size(); ++b) {
    if (taken[b]) continue;
    int under = 0;
    for (size_t o = 0; o < obscured.size(); ++o) {
      const bool near = (blobs[b] - predictions[o].predicted_px).norm() <= predictions[o].gate_px;
      if (near && areas[b] >= config_.merge_area_ratio * std::max(1, obscured[o]->area_px)) ++under;
    }
    if (under >= 2) {
      taken[b] = true;
      ++counters_.merges;
    }
  }
  for (const Assignment& m : Associator::assign(predictions, blobs, taken)) {
    Track& t = *obscured[m.object];
    taken[m.blob] = true;
    if (partly_hidden(t, areas[m.blob], config_.reacquire_area_ratio)) {
      ++counters_.partial_blobs;  // still mostly under the arm: keep coasting
      continue;
    }
    ++counters_.reacquired;
    see(t, blobs[m.blob], areas[m.blob], true);
    if (!inside_field(t.filter.position(), config_.visible_escape_margin_mm)) {
      kill(t, "re-acquired outside the field");
    }
  }
}

void WorldModel::stage3_dead_reckon() {
  for (auto& [id, t] : tracks_) {
    if (t.state != ObjectState::kObscured) continue;
    t.estimate_px = dead_reckoned(t);
    if (!inside_field(t.estimate_px, config_.hidden_escape_margin_mm)) {
      kill(t, "reckoned outside the field");
    } else if (now_s_ - t.seen_s > config_.max_obscured_s) {
      kill(t, "hidden too long");
    }
  }
}

void WorldModel::stage4_new(const std::vector<Eigen::Vector2d>& blobs,
                            const std::vector<int>& areas, const std::vector<bool>& taken) {
  for (size_t b = 0; b < blobs.size(); ++b) {
    if (taken[b]) continue;
    if (!inside_field(blobs[b])) {
      ++counters_.blobs_outside_field;
      continue;
    }
    Track t{.id = next_id_, .filter = DoubleAlphaBetaFilter(config_.filter)};
    ++next_id_;
    ++counters_.objects_created;
    note_birth_near_hidden(t.id, blobs[b], areas[b]);
    if (areas[b] < config_.partial_area_ratio * whole_mark_area_px_) {
      // Partly hidden: an obscured object at the blob, measured once whole.
      ++counters_.born_partial;
      t.state = ObjectState::kObscured;
      t.seen_px = blobs[b];
      t.seen_s = now_s_;
      t.estimate_px = blobs[b];
      t.area_px = areas[b];
      t.usual_area_px = whole_mark_area_px_;
      tracks_.emplace(t.id, std::move(t));
      continue;
    }
    see(t, blobs[b], areas[b], false);
    tracks_.emplace(t.id, std::move(t));
  }
}

void WorldModel::note_birth_near_hidden(int id, const Eigen::Vector2d& blob_px, int area_px) {
  // Only the obscured object nearest the new blob matters: had the blob been
  // within its gate it would have been re-acquired, not born.
  const Track* nearest = nullptr;
  double nearest_px = std::numeric_limits<double>::infinity();
  for (const auto& [other_id, t] : tracks_) {
    if (t.state != ObjectState::kObscured) continue;
    const double d = (dead_reckoned(t) - blob_px).norm();
    if (d < nearest_px) {
      nearest_px = d;
      nearest = &t;
    }
  }
  if (nearest == nullptr || nearest_px > config_.obscured_gate_max_px * 1.5) return;
  const double hidden_s = now_s_ - nearest->seen_s;
  const double gate =
      std::min(config_.obscured_gate_max_px,
               config_.obscured_gate_px + config_.obscured_gate_growth_px_s * hidden_s);
  char text[240];
  std::snprintf(text, sizeof text,
                "object %d born at (%.0f, %.0f) px, area %d px: hidden object %d is %.1f px away "
                "(gate %.1f px, hidden %.2f s, its usual area %.0f px)",
                id, blob_px.x(), blob_px.y(), area_px, nearest->id, nearest_px, gate, hidden_s,
                nearest->usual_area_px);
  events_.emplace_back(text);
}

std::vector<ObjectEstimate> WorldModel::objects() const {
  std::vector<ObjectEstimate> out;
  out.reserve(tracks_.size());
  const Eigen::Matrix2d linear = mark_map_.block<2, 2>(0, 0);
  for (const auto& [id, t] : tracks_) {
    ObjectEstimate e;
    e.id = id;
    e.state = t.state;
    e.position_px = t.estimate_px;
    e.position_mm = mark_map_ * t.estimate_px.homogeneous();
    e.velocity_px_s = t.filter.velocity();
    e.velocity_mm_s = linear * e.velocity_px_s;
    e.velocity_raw_px_s = t.raw_velocity_px_s;
    e.velocity_first_px_s = t.filter.first().velocity();
    e.since_seen_s = t.state == ObjectState::kVisible ? 0.0 : now_s_ - t.seen_s;
    e.area_px = t.area_px;
    out.push_back(e);
  }
  return out;
}

}  // namespace ephor::worldmodel
