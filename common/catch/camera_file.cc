#include "common/catch/camera_file.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include <google/protobuf/text_format.h>

#include "common/catch/camera.pb.h"
#include "common/config/text_proto.h"

namespace ephor::catching {
namespace {

std::string fmt(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

double finite(const TextProto& src, const std::string& field, bool has, double v) {
  if (!has) src.fail(field, "missing");
  if (!std::isfinite(v)) src.fail(field, "must be a finite number, got " + fmt(v));
  return v;
}

CameraIntrinsics from_proto(const config::Camera& p, const TextProto& src) {
  CameraIntrinsics c;
  if (!p.has_width()) src.fail("width", "missing");
  if (!p.has_height()) src.fail("height", "missing");
  if (p.width() <= 0) src.fail("width", "must be > 0 px, got " + std::to_string(p.width()));
  if (p.height() <= 0) src.fail("height", "must be > 0 px, got " + std::to_string(p.height()));
  c.width = p.width();
  c.height = p.height();
  c.fx = finite(src, "fx", p.has_fx(), p.fx());
  c.fy = finite(src, "fy", p.has_fy(), p.fy());
  c.cx = finite(src, "cx", p.has_cx(), p.cx());
  c.cy = finite(src, "cy", p.has_cy(), p.cy());
  if (c.fx <= 0.0) src.fail("fx", "focal length must be > 0 px, got " + fmt(c.fx));
  if (c.fy <= 0.0) src.fail("fy", "focal length must be > 0 px, got " + fmt(c.fy));
  if (c.cx < -0.5 || c.cx > c.width - 0.5)
    src.fail("cx", "principal point " + fmt(c.cx) + " px is outside the image (-0.5.." +
                       fmt(c.width - 0.5) + ")");
  if (c.cy < -0.5 || c.cy > c.height - 0.5)
    src.fail("cy", "principal point " + fmt(c.cy) + " px is outside the image (-0.5.." +
                       fmt(c.height - 0.5) + ")");
  const int n = p.distortion_size();
  if (n != 0 && n != 4 && n != 5 && n != 8 && n != 12 && n != 14)
    src.fail("distortion[0]",
             "OpenCV takes 4, 5, 8, 12 or 14 coefficients, got " + std::to_string(n));
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(p.distortion(i)))
      src.fail("distortion[" + std::to_string(i) + "]", "coefficient is not finite");
    c.distortion.push_back(p.distortion(i));
  }
  return c;
}

template <typename F>
auto prefixed(F&& f) {
  try {
    return f();
  } catch (const ConfigError& e) {
    throw ConfigError(std::string("camera file ") + e.what());
  }
}

}  // namespace

CameraIntrinsics load_camera_file(const std::string& path) {
  return prefixed([&] {
    config::Camera p;
    const TextProto src(path, &p);
    return from_proto(p, src);
  });
}

CameraIntrinsics parse_camera_text(const std::string& text, const std::string& name) {
  return prefixed([&] {
    config::Camera p;
    const auto src = TextProto::from_string(text, name, &p);
    return from_proto(p, *src);
  });
}

std::string camera_to_text(const CameraIntrinsics& camera, const std::string& header_comment) {
  config::Camera p;
  p.set_width(camera.width);
  p.set_height(camera.height);
  p.set_fx(camera.fx);
  p.set_fy(camera.fy);
  p.set_cx(camera.cx);
  p.set_cy(camera.cy);
  for (double k : camera.distortion) p.add_distortion(k);
  std::string body;
  if (!google::protobuf::TextFormat::PrintToString(p, &body))
    throw ConfigError("cannot print the camera as text");
  std::string out;
  std::istringstream lines(header_comment);
  std::string line;
  while (std::getline(lines, line)) out += "# " + line + "\n";
  return out + body;
}

void save_camera_file(const CameraIntrinsics& camera, const std::string& path,
                      const std::string& header_comment) {
  const std::string text = camera_to_text(camera, header_comment);
  parse_camera_text(text, path);  // the same checks as loading it back
  std::ofstream out(path);
  if (!out) throw ConfigError("camera file " + path + ": cannot open file for writing");
  out << text;
  out.close();
  if (!out) throw ConfigError("camera file " + path + ": write failed");
}

std::string frame_size_problem(const CameraIntrinsics& camera, const std::string& camera_path,
                               int width, int height, const std::string& frames_name) {
  if (width == camera.width && height == camera.height) return "";
  return frames_name + " are " + std::to_string(width) + " x " + std::to_string(height) +
         " px but the camera file " + camera_path + " says " + std::to_string(camera.width) +
         " x " + std::to_string(camera.height) + " px";
}

}  // namespace ephor::catching
