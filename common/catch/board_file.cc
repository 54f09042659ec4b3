#include "common/catch/board_file.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include <google/protobuf/text_format.h>

#include "common/config/text_proto.h"
#include "common/catch/board.pb.h"

namespace ephor::catching {
namespace {

std::string fmt(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

double positive(const TextProto& src, const std::string& field, bool has, double v) {
  if (!has) src.fail(field, "missing");
  if (!std::isfinite(v) || v <= 0.0)
    src.fail(field, "must be a positive finite number, got " + fmt(v));
  return v;
}

double finite(const TextProto& src, const std::string& field, bool has, double v) {
  if (!has) src.fail(field, "missing");
  if (!std::isfinite(v)) src.fail(field, "must be a finite number, got " + fmt(v));
  return v;
}

BoardSpec from_proto(const config::Board& p, const TextProto& src) {
  BoardSpec b;
  b.width_mm = positive(src, "width_mm", p.has_width_mm(), p.width_mm());
  b.height_mm = positive(src, "height_mm", p.has_height_mm(), p.height_mm());
  b.ball_diameter_mm =
      positive(src, "ball_diameter_mm", p.has_ball_diameter_mm(), p.ball_diameter_mm());
  if (b.ball_diameter_mm >= std::min(b.width_mm, b.height_mm))
    src.fail("ball_diameter_mm", "ball (" + fmt(b.ball_diameter_mm) +
                                     " mm) does not fit on the board (" + fmt(b.width_mm) + " x " +
                                     fmt(b.height_mm) + " mm)");
  if (p.circle_size() != 4)
    throw ConfigError(src.path() +
                      ": needs exactly 4 circles (top-left, top-right, bottom-left, "
                      "bottom-right), has " +
                      std::to_string(p.circle_size()));
  for (int i = 0; i < 4; ++i) {
    const auto& c = p.circle(i);
    const std::string f = "circle[" + std::to_string(i) + "]";
    BoardCircle& out = b.circles[static_cast<size_t>(i)];
    out.x_mm = finite(src, f + ".x_mm", c.has_x_mm(), c.x_mm());
    out.y_mm = finite(src, f + ".y_mm", c.has_y_mm(), c.y_mm());
    out.diameter_mm = positive(src, f + ".diameter_mm", c.has_diameter_mm(), c.diameter_mm());
    const double r = out.diameter_mm / 2.0;
    if (out.x_mm - r < 0.0 || out.x_mm + r > b.width_mm || out.y_mm - r < 0.0 ||
        out.y_mm + r > b.height_mm)
      src.fail(f, std::string(circle_name(i)) + " circle (centre " + fmt(out.x_mm) + ", " +
                      fmt(out.y_mm) + " mm, diameter " + fmt(out.diameter_mm) +
                      " mm) is not inside the board (0..0 to " + fmt(b.width_mm) + ", " +
                      fmt(b.height_mm) + " mm)");
  }
  // Corner order: top-left (small x, small y), top-right (large x, small y),
  // bottom-left (small x, large y), bottom-right (large x, large y).
  const auto& c = b.circles;
  auto order = [&](int i, const char* what) {
    src.fail("circle[" + std::to_string(i) + "]",
             std::string(circle_name(i)) + " circle is out of order: " + what +
                 " (circles are top-left, top-right, bottom-left, bottom-right)");
  };
  if (!(c[0].x_mm < c[1].x_mm)) order(1, "its x is not larger than top-left's");
  if (!(c[2].x_mm < c[3].x_mm)) order(3, "its x is not larger than bottom-left's");
  if (!(c[0].y_mm < c[2].y_mm)) order(2, "its y is not larger than top-left's");
  if (!(c[1].y_mm < c[3].y_mm)) order(3, "its y is not larger than top-right's");
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {
      const double d = std::hypot(c[static_cast<size_t>(i)].x_mm - c[static_cast<size_t>(j)].x_mm,
                                  c[static_cast<size_t>(i)].y_mm - c[static_cast<size_t>(j)].y_mm);
      if (d < (c[static_cast<size_t>(i)].diameter_mm + c[static_cast<size_t>(j)].diameter_mm) / 2.0)
        src.fail(
            "circle[" + std::to_string(j) + "]",
            std::string(circle_name(j)) + " circle overlaps the " + circle_name(i) + " circle");
    }
  return b;
}

template <typename F>
auto prefixed(F&& f) {
  try {
    return f();
  } catch (const ConfigError& e) {
    throw ConfigError(std::string("board file ") + e.what());
  }
}

}  // namespace

const char* circle_name(int index) {
  static const char* const kNames[] = {"top-left", "top-right", "bottom-left", "bottom-right"};
  return index >= 0 && index < 4 ? kNames[index] : "(no such circle)";
}

BoardSpec load_board_file(const std::string& path) {
  return prefixed([&] {
    config::Board p;
    const TextProto src(path, &p);
    return from_proto(p, src);
  });
}

BoardSpec parse_board_text(const std::string& text, const std::string& name) {
  return prefixed([&] {
    config::Board p;
    const auto src = TextProto::from_string(text, name, &p);
    return from_proto(p, *src);
  });
}

std::string board_to_text(const BoardSpec& board, const std::string& header_comment) {
  config::Board p;
  p.set_width_mm(board.width_mm);
  p.set_height_mm(board.height_mm);
  p.set_ball_diameter_mm(board.ball_diameter_mm);
  for (const BoardCircle& c : board.circles) {
    auto* out = p.add_circle();
    out->set_x_mm(c.x_mm);
    out->set_y_mm(c.y_mm);
    out->set_diameter_mm(c.diameter_mm);
  }
  std::string body;
  if (!google::protobuf::TextFormat::PrintToString(p, &body))
    throw ConfigError("cannot print the board as text");
  std::string out;
  std::istringstream lines(header_comment);
  std::string line;
  while (std::getline(lines, line)) out += "# " + line + "\n";
  return out + body;
}

void save_board_file(const BoardSpec& board, const std::string& path,
                     const std::string& header_comment) {
  const std::string text = board_to_text(board, header_comment);
  parse_board_text(text, path);  // the same checks as loading it back
  std::ofstream out(path);
  if (!out) throw ConfigError("board file " + path + ": cannot open file for writing");
  out << text;
  out.close();
  if (!out) throw ConfigError("board file " + path + ": write failed");
}

}  // namespace ephor::catching
