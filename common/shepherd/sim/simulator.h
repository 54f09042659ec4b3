#pragma once
// Simulator: the whole simulated work cell in one steppable object - the
// sheep World, the PUMA 560 under its ArmServo, and the overhead camera. The
// arm's tool tip is fed to the world at every step (so a lowered tool turns
// sheep) and the arm's links are drawn over the field by the camera.
//
// No wall clock inside: step(dt) advances simulated time; ephor-sim ties it to
// the monotonic clock, benchmarks and tests run it as fast as they like.
//
// Arm as the camera sees it (ArmPart capsules in F; radii are rough PUMA 560
// dimensions): pedestal and trunk 70 mm, shoulder and upper arm 60 mm,
// forearm 45 mm, wrist and flange housing 40 mm (the first half of the tool
// length below the wrist centre), tool rod 8 mm. With the tool lowered over a
// sheep, the wrist housing above it hides the sheep's mark - as the paper's
// arm did (section 4.2, obscured objects).
//
// Threading: not thread-safe; one owner (or one mutex) for everything.

#include <cstdint>
#include <optional>
#include <vector>

#include "common/arm/arm_servo.h"
#include "common/arm/puma560.h"
#include "common/geometry/workcell.h"
#include "common/shepherd/sim/camera_renderer.h"
#include "common/shepherd/sim/world.h"

namespace ephor::sim {

struct SimulatorConfig {
  WorldConfig world;  // world.workcell is the work cell of the arm and camera too
  CameraConfig camera;
  CloudFieldConfig clouds;  // clouds between the camera and the field (0 = none)
  // False: the camera does not see the arm (it never hides a mark). For
  // measuring what the arm's occlusion costs the tracking; the arm still moves
  // and touches sheep.
  bool arm_in_image = true;
  double servo_step_s = 0.001;  // the servo integrates in steps no longer than this, s
};

// Ground truth of one sheep in one frame.
struct SheepTruth {
  SheepState state;
  MarkView view;  // where the camera sees its mark, and whether the arm hides it
};

// What the camera needs to draw one frame: copied under the owner's lock, drawn outside it.
struct Scene {
  double time_s = 0.0;
  std::vector<SheepState> sheep;
  std::vector<ArmPart> arm;
  int32_t escapes = 0;
  int32_t saves = 0;
  std::optional<ToolLight> tool_light;  // set while the calibration light is on
  std::vector<Cloud> clouds;
};

struct GroundTruth {
  double time_s = 0.0;  // simulated time of this state, s
  std::vector<SheepTruth> sheep;
  int32_t escapes = 0;
  int32_t saves = 0;
};

// The arm's parts for the camera: capsules in F (mm) for joints q.
std::vector<ArmPart> arm_parts(const arm::Puma560& puma, const geometry::Workcell& cell,
                               const arm::Joints& q);

class Simulator {
 public:
  // Throws std::invalid_argument for a bad config; the arm starts at park_joints.
  explicit Simulator(SimulatorConfig config);

  // Advances arm and world by dt_s (> 0, finite) seconds.
  void step(double dt_s);

  // See ArmServo::follow.
  bool follow(const JointTrajectory& trajectory) { return servo_.follow(trajectory); }
  const ServoState& servo() const { return servo_.state(); }
  // Tool tip in F, mm.
  Eigen::Vector3d tool_tip_mm() const;
  // The calibration light on the tool tip (shepherd_tool_light_t): while on, the
  // camera draws it at the tip (CameraRenderer's ToolLight).
  void set_tool_light(bool on) { tool_light_on_ = on; }
  bool tool_light() const { return tool_light_on_; }

  // The current state as the camera sees it; render() also draws the frame
  // (width * height bytes, row-major).
  GroundTruth truth() const;
  GroundTruth render(std::vector<uint8_t>& image);
  Scene scene() const;
  // Draws `scene` with `camera` (any renderer: ephor-sim's camera thread has its own).
  static GroundTruth render(const Scene& scene, CameraRenderer& camera,
                            std::vector<uint8_t>& image);

  World& world() { return world_; }
  const World& world() const { return world_; }
  const CameraRenderer& camera() const { return camera_; }
  const arm::Puma560& puma() const { return puma_; }
  const SimulatorConfig& config() const { return config_; }

  // Restarts the world with `seed`; the arm stays where it is.
  void reset(uint64_t seed) { world_.reset(seed); }

 private:
  // Hands the world the tool's tip and orientation for the arm's joints now.
  void set_world_tool();

  SimulatorConfig config_;
  arm::Puma560 puma_;
  World world_;
  ArmServo servo_;
  CameraRenderer camera_;
  CloudField clouds_;
  bool tool_light_on_ = false;
};

}  // namespace ephor::sim
