#pragma once
// CommandValidator: turns one control request of the display page (a command
// name and its parameters, as strings from the HTTP query) into the full
// desired state to publish, or a reason why it is refused. Nothing is sent for
// a refused request: the caller answers HTTP 400 with the reason.
//
// Every control is full state (libbot2 procman style): the validator starts
// from the current desired state and changes only what the command names, so
// the message published carries everything the receiver needs.
//
// Commands (parameter "value" unless noted):
//   pause    true|false            vision paused (the paper's scan button)
//   mode     blobify|trackify      vision search mode
//   scan     full|axis             vision blob scan
//   planner  single|multi|lookahead
//   sheep    integer 0..64         simulator herd size
//   box      u, v (px, inside the image), half (px, 2..200), visible true|false
// (The page's STOP, cmd=estop, is every arm system's: DisplayServer's.)
//
// Pure: no LCM, no I/O; not thread-safe (the caller holds its lock).

#include <map>
#include <string>

namespace ephor::display {

// Desired vision state (mirrors shepherd_vision_cmd_t).
struct VisionControl {
  bool paused = false;
  int mode = 0;        // shepherd_vision_cmd_t.MODE_BLOBIFY (0) or MODE_TRACKIFY (1)
  int scan = 0;        // shepherd_vision_cmd_t.SCAN_FULL (0) or SCAN_AXIS (1)
  int threshold = -1;  // grey level 1..254, or -1 = pick automatically
};

// Desired simulator state (mirrors shepherd_sim_cmd_t; reset is always false here).
struct SimControl {
  int sheep = 4;
  int seed = 1;
};

// The calibration box (mirrors shepherd_display_box_t). Image px.
struct CalibrationBox {
  bool visible = false;
  double u = 0.0;
  double v = 0.0;
  double half_size_px = 12.0;
};

// Everything the page can steer.
struct Controls {
  VisionControl vision;
  SimControl sim;
  std::string planner = "multi";
  CalibrationBox box;
};

enum class Target { kNone, kVision, kSim, kPlanner, kBox };

struct CommandResult {
  bool ok = false;
  std::string reason;  // why it was refused (ok == false)
  Target target = Target::kNone;
  Controls controls;  // the new desired state (ok == true); publish the part `target` names
};

class CommandValidator {
 public:
  // image_width_px / image_height_px bound the calibration box centre.
  CommandValidator(int image_width_px, int image_height_px);

  void set_image_size(int width_px, int height_px);

  // Validates `command` with its `params` against `current`. Never throws.
  CommandResult validate(const std::string& command,
                         const std::map<std::string, std::string>& params,
                         const Controls& current) const;

 private:
  int width_px_;
  int height_px_;
};

}  // namespace ephor::display
