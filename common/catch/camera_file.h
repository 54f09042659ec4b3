#pragma once
// The camera file (Protobuf text, schema camera.proto): a pinhole camera's
// image size and intrinsics in px with optional OpenCV distortion.
//
//   width: 640  height: 480
//   fx: 600  fy: 600  cx: 319.5  cy: 239.5
//   distortion: [-0.1, 0.01, 0, 0]     # optional, k1 k2 p1 p2 [k3 ...]

#include <string>

#include "common/catch/board_model.h"

namespace ephor::catching {

// Reads and checks a camera file. Throws ephor::ConfigError (a
// std::runtime_error) whose message starts "camera file <path>" and names the
// problem and its line: unreadable file, syntax error, missing field,
// non-positive size or focal length, principal point outside the image,
// non-finite values, a distortion vector of a length OpenCV does not accept
// (0, 4, 5, 8, 12 or 14).
CameraIntrinsics load_camera_file(const std::string& path);
// Same from text in memory; `name` stands for the file in messages.
CameraIntrinsics parse_camera_text(const std::string& text, const std::string& name);

// The camera as camera-file text (round-trips through parse_camera_text).
std::string camera_to_text(const CameraIntrinsics& camera, const std::string& header_comment = "");
// Checks `camera` as the loader would, then writes it. Throws ConfigError.
void save_camera_file(const CameraIntrinsics& camera, const std::string& path,
                      const std::string& header_comment = "");

// Whether frames of `width` x `height` px fit the camera file `camera` was
// read from (`camera_path`): "" when they do, else a message naming both
// sizes, e.g. "frames of clip.avi are 800 x 600 px but the camera file
// cam.pbtxt says 640 x 480 px". The vision process and the offline tracker
// refuse such frames: intrinsics of another size would misplace every ray.
std::string frame_size_problem(const CameraIntrinsics& camera, const std::string& camera_path,
                               int width, int height, const std::string& frames_name);

}  // namespace ephor::catching
