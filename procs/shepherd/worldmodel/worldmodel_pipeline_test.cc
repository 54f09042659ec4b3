// The world model on real blobs: ephor-sim -> ephor-vision -> ephor-worldmodel
// in a private network namespace, scored against the simulator's ground
// truth: every sheep on the field is tracked, to within a few mm, and keeps
// its id, also when the arm (sent straight to the simulator's servo on
// ARM_TRAJECTORY) is parked across a sheep's path and hides it for a while.

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <mutex>

#include <gtest/gtest.h>

#include "common/arm/arm_workcell.h"
#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "ephor/joint_state_t.hpp"
#include "ephor/joint_trajectory_t.hpp"
#include "ephor/shepherd_ground_truth_t.hpp"
#include "ephor/shepherd_objects_t.hpp"
#include "tests/integration/harness.h"

namespace ephor::testing {
namespace {

using std::chrono::seconds;

// Pairs OBJECTS with the GROUND_TRUTH of the same frame (same utime) and
// scores them.
class Scorer {
 public:
  Scorer() : bus_("", "scorer") {
    bus_.subscribe<shepherd_ground_truth_t>(channels::kGroundTruth,
                                            [this](const shepherd_ground_truth_t& m) {
                                              std::lock_guard<std::mutex> lock(mutex_);
                                              truth_[m.utime] = m;
                                              while (truth_.size() > 300)
                                                truth_.erase(truth_.begin());
                                            });
    bus_.subscribe<joint_state_t>(channels::kArmServo, [this](const joint_state_t& m) {
      std::lock_guard<std::mutex> lock(mutex_);
      q_ = arm::Joints(m.q);
    });
    bus_.subscribe<shepherd_objects_t>(channels::kObjects, [this](const shepherd_objects_t& m) {
      std::lock_guard<std::mutex> lock(mutex_);
      const auto it = truth_.find(m.utime);
      if (it == truth_.end()) {
        ++unpaired_;
        return;
      }
      score(it->second, m);
    });
    bus_.start();
  }
  ~Scorer() { bus_.stop(); }

  struct Score {
    int frames = 0;
    int unpaired = 0;
    int sheep_frames = 0;  // visible sheep on the field, summed over frames
    int tracked = 0;       // ... with a visible object within 25 mm
    double error_sum_mm = 0.0;
    double error_max_mm = 0.0;
    int id_switches = 0;      // a sheep's object id changed
    int occluded_frames = 0;  // sheep hidden by the arm, summed over frames
    int occluded_kept = 0;    // ... whose object was still alive (obscured) near it
  };
  std::optional<shepherd_ground_truth_t> latest_truth() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (truth_.empty()) return std::nullopt;
    return truth_.rbegin()->second;
  }
  std::optional<arm::Joints> arm_joints() {
    std::lock_guard<std::mutex> lock(mutex_);
    return q_;
  }
  // Frames sheep `id` was seen hidden after we had an object for it, and
  // visible since then.
  std::pair<int, int> hidden_then_visible(int id) {
    std::lock_guard<std::mutex> lock(mutex_);
    return {hidden_[id], visible_after_[id]};
  }
  void forget_occlusions(int id) {
    std::lock_guard<std::mutex> lock(mutex_);
    hidden_[id] = 0;
    visible_after_[id] = 0;
  }
  Bus& bus() { return bus_; }

  Score get() {
    std::lock_guard<std::mutex> lock(mutex_);
    Score s = score_;
    s.unpaired = unpaired_;
    return s;
  }

 private:
  void score(const shepherd_ground_truth_t& truth, const shepherd_objects_t& objs) {
    ++score_.frames;
    for (const auto& sheep : truth.sheep) {
      if (!sheep.on_field) continue;
      // Stay clear of the field edge, where a sheep may be dead or new.
      if (sheep.x_mm < 30 || sheep.y_mm < 30 || sheep.x_mm > 1189 || sheep.y_mm > 884) continue;
      const shepherd_object_t* best = nullptr;
      double best_d = 1e9;
      for (const auto& o : objs.objects) {
        if (o.state == shepherd_object_t::STATE_DEAD) continue;
        const double d = std::hypot(o.x_mm - sheep.x_mm, o.y_mm - sheep.y_mm);
        if (d < best_d) {
          best_d = d;
          best = &o;
        }
      }
      if (sheep.visible) {
        ++score_.sheep_frames;
        if (hidden_[sheep.id] > 0) ++visible_after_[sheep.id];
        if (best != nullptr && best->state == shepherd_object_t::STATE_VISIBLE && best_d < 25.0) {
          ++score_.tracked;
          score_.error_sum_mm += best_d;
          score_.error_max_mm = std::max(score_.error_max_mm, best_d);
        }
      } else if (const auto known = id_of_.find(sheep.id); known != id_of_.end()) {
        // Hidden by the arm after we had seen it: its object must live on,
        // dead-reckoned near it.
        ++score_.occluded_frames;
        ++hidden_[sheep.id];
        for (const auto& o : objs.objects)
          if (o.id == known->second && o.state != shepherd_object_t::STATE_DEAD &&
              std::hypot(o.x_mm - sheep.x_mm, o.y_mm - sheep.y_mm) < 60.0f)
            ++score_.occluded_kept;
      }
      if (best != nullptr && best_d < 25.0 && best->state == shepherd_object_t::STATE_VISIBLE) {
        auto [it, inserted] = id_of_.emplace(sheep.id, best->id);
        if (!inserted && it->second != best->id) {
          ++score_.id_switches;
          it->second = best->id;
        }
      }
    }
  }

  Bus bus_;
  std::mutex mutex_;
  std::map<int64_t, shepherd_ground_truth_t> truth_;
  std::map<int, int> id_of_;  // sim sheep id -> object id
  std::map<int, int> hidden_, visible_after_;
  std::optional<arm::Joints> q_;
  Score score_;
  int unpaired_ = 0;
};

TEST(WorldModelPipeline, TracksSimulatedSheepWithStableIds) {
  Scorer scorer;
  Processes procs;
  const std::vector<std::pair<std::string, std::string>> env = {{"EPHOR_HOST", "testhost"}};
  procs.start("sim", bin("ephor-sim"),
              {"--no-mlock", "--name", "sim", "--sheep", "4", "--seed", "3",
               // The 30 mm/s stress speed: this test wants sheep that cross the arm's
               // reach and the image within its seconds (at the 8 mm/s default they barely move).
               "--speed-mm-s", "30"},
              env);
  procs.start("vision", bin("ephor-vision"), {"--no-mlock", "--name", "vision"}, env);
  procs.start("worldmodel", bin("ephor-worldmodel"), {"--no-mlock", "--name", "worldmodel"}, env);
  ASSERT_TRUE(wait_until([&] { return scorer.get().frames >= 30; }, seconds(20)))
      << "no OBJECTS paired with GROUND_TRUTH";
  // 10 s of tracking at 30 Hz.
  ASSERT_TRUE(wait_until([&] { return scorer.get().frames >= 300; }, seconds(20)));

  // Then the arm goes over a sheep: the tool in the elevation plane where the
  // sheep will be in 4 s, so it walks under it and is hidden for a while.
  const geometry::Workcell cell;
  const arm::Puma560 puma = arm::make_puma(cell);
  int target = -1;
  ASSERT_TRUE(wait_until(
      [&] {
        const auto truth = scorer.latest_truth();
        const auto q = scorer.arm_joints();
        if (!truth || !q) return false;
        for (const auto& sh : truth->sheep) {
          if (!sh.on_field || !sh.visible) continue;
          const double speed = sh.speed_mm_s, heading = sh.heading_rad;
          const double x = double{sh.x_mm} + 4.0 * speed * std::cos(heading);
          const double y = double{sh.y_mm} + 4.0 * speed * std::sin(heading);
          if (x < 150 || y < 150 || x > cell.field_length_mm - 150 ||
              y > cell.field_width_mm - 150 || arm::distance_from_column_mm(cell, x, y) < 420)
            continue;
          // Crossing under the arm (which reaches out from the column), not
          // walking along it, so that the sheep comes out again.
          const Eigen::Vector2d radial =
              Eigen::Vector2d(x - cell.base_x_mm, y - cell.base_y_mm).normalized();
          if (std::abs(radial.dot(Eigen::Vector2d(std::cos(heading), std::sin(heading)))) > 0.5)
            continue;
          const auto goal = puma.nearest_inverse(
              arm::tool_down_pose(cell, x, y, cell.elevation_plane_z_mm, heading), *q);
          if (!goal) continue;
          joint_trajectory_t traj{};
          traj.seq = 1;
          traj.num_points = 2;
          traj.t_s = {0.0f, 2.5f};
          std::vector<double> q0(q->data(), q->data() + 6), q1(goal->data(), goal->data() + 6);
          traj.q = {q0, q1};
          traj.qd = {std::vector<double>(6, 0.0), std::vector<double>(6, 0.0)};
          scorer.forget_occlusions(sh.id);
          scorer.bus().publish(channels::kArmTrajectory, traj);
          target = sh.id;
          return true;
        }
        return false;
      },
      seconds(20)))
      << "no sheep to pass the arm over";
  // Hidden for a while, then out from under the arm again.
  EXPECT_TRUE(wait_until(
      [&] {
        const auto [hidden, visible] = scorer.hidden_then_visible(target);
        return hidden >= 15 && visible >= 30;
      },
      seconds(25)))
      << "sheep " << target << " hidden " << scorer.hidden_then_visible(target).first
      << " frames, visible after " << scorer.hidden_then_visible(target).second;
  const auto s = scorer.get();
  const double mean_mm = s.tracked > 0 ? s.error_sum_mm / s.tracked : -1.0;
  std::printf(
      "frames %d (unpaired %d); visible sheep-frames %d, tracked %d, error mean %.2f mm max %.2f "
      "mm; id switches %d; occluded sheep-frames %d, kept %d; arm over sheep %d: hidden %d "
      "frames\n",
      s.frames, s.unpaired, s.sheep_frames, s.tracked, mean_mm, s.error_max_mm, s.id_switches,
      s.occluded_frames, s.occluded_kept, target, scorer.hidden_then_visible(target).first);
  EXPECT_GT(s.sheep_frames, 0);
  // Marks partly under the arm (still "visible" to the simulator) are
  // reported obscured on purpose: their centroids are off.
  // 0.97 on a quiet machine; 96.97 % was seen under CI's load (2026-11-28).
  EXPECT_GE(s.tracked, 0.95 * s.sheep_frames);
  EXPECT_LT(mean_mm, 3.0);
  EXPECT_EQ(s.id_switches, 0);
  EXPECT_GE(s.occluded_kept, s.occluded_frames * 9 / 10);
  EXPECT_TRUE(procs.exits().empty());
}

}  // namespace
}  // namespace ephor::testing
