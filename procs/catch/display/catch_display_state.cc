#include "procs/catch/display/catch_display_state.h"

#include <algorithm>
#include <cmath>

#include "common/catch/board_survey.h"
#include "common/display/json_format.h"

namespace ephor::catch_display {
namespace {

using display::age_ms;
using nlohmann::json;

using display::r1;
using display::rounded;

// b - a in s, for times in us from the messages (any int64_t: their
// difference as int64_t may overflow).
double seconds_between(int64_t a_us, int64_t b_us) {
  return (static_cast<double>(b_us) - static_cast<double>(a_us)) / 1e6;
}

constexpr double kPi = 3.14159265358979323846;

json point(const std::optional<Eigen::Vector2d>& p) {
  if (!p) return nullptr;
  return json::array({r1(p->x()), r1(p->y())});
}

// A polyline of the points that project (an unprojectable one is left out).
template <class Points>
json polyline(const BoardProjector& proj, const Points& pts, bool world) {
  json a = json::array();
  for (const auto& p : pts) {
    const auto uv = world ? proj.project_world(p) : proj.project_board(p);
    if (uv) a.push_back(point(uv));
  }
  return a;
}

const char* world_status(int s) {
  switch (s) {
    case 0:
      return "no ball";
    case 1:
      return "tracking";
    case 2:
      return "rejected";
    case 3:
      return "exited";
    default:
      return "unknown";
  }
}

const char* truth_phase(int p) {
  switch (p) {
    case 0:
      return "waiting";
    case 1:
      return "rolling";
    case 2:
      return "flying";
    case 3:
      return "done";
    default:
      return "unknown";
  }
}

bool finite2(const std::array<double, 2>& a) { return std::isfinite(a[0]) && std::isfinite(a[1]); }

}  // namespace

CatchDisplayState::CatchDisplayState(catching::BoardSpec board, catching::CameraIntrinsics camera,
                                     CatchDisplayOptions options)
    : board_(board), options_(options), projector_(std::move(camera)) {}

void CatchDisplayState::on_frame(int64_t frame_index, int width_px, int height_px, int64_t now_us) {
  frame_index_ = frame_index;
  width_px_ = width_px;
  height_px_ = height_px;
  frame_us_ = now_us;
}

void CatchDisplayState::on_board_pose(const BoardPoseView& pose, int64_t now_us) {
  pose_ = pose;
  pose_us_ = now_us;
  bool finite =
      std::all_of(pose.r.begin(), pose.r.end(), [](double x) { return std::isfinite(x); }) &&
      std::all_of(pose.t_mm.begin(), pose.t_mm.end(), [](double x) { return std::isfinite(x); });
  if (!pose.valid || !finite) {
    projector_.set_board_to_camera(std::nullopt);
    return;
  }
  catching::Pose p = catching::Pose::Identity();
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) p.linear()(i, k) = pose.r[static_cast<size_t>(3 * i + k)];
    p.translation()[i] = pose.t_mm[static_cast<size_t>(i)];
  }
  projector_.set_board_to_camera(p);
}

void CatchDisplayState::on_survey(const SurveyView& survey, int64_t /*now_us*/) {
  surveyed_ = true;
  std::string why;
  placement_ = catching::placement_from_survey(board_, survey.board_mm, survey.world_mm, why);
  survey_problem_ = placement_ ? "" : why;
  projector_.set_board_to_world(
      placement_ ? std::optional<catching::Pose>(catching::board_to_world(board_, *placement_))
                 : std::nullopt);
}

void CatchDisplayState::on_ball(const BallView& ball, int64_t now_us) {
  ball_ = ball;
  ball_us_ = now_us;
}

void CatchDisplayState::on_world(const WorldView& world, int64_t now_us) {
  world_ = world;
  world_us_ = now_us;
}

void CatchDisplayState::on_truth(const TruthView& truth, int64_t now_us) {
  truth_ = truth;
  truth_us_ = now_us;
}

void CatchDisplayState::on_arm(const ArmView& arm, int64_t now_us) {
  arm_ = arm;
  arm_us_ = now_us;
}

json CatchDisplayState::board_json(int64_t now_us) const {
  if (!pose_) return nullptr;
  json j = {{"valid", pose_->valid},
            {"reason", pose_->reason},
            {"rms_px", rounded(pose_->reprojection_rms_px, 2)},
            {"surveyed", placement_.has_value()},
            {"survey_problem", survey_problem_},
            {"age_ms", r1(age_ms(pose_us_, now_us))}};
  if (placement_) j["incline_deg"] = r1(placement_->incline_rad * 180.0 / kPi);
  const double w = board_.width_mm, h = board_.height_mm;
  // The face's outline (z = 0): top-left, top-right, bottom-right, bottom-left in B.
  const std::array<Eigen::Vector3d, 4> corners{{{0, 0, 0}, {w, 0, 0}, {w, h, 0}, {0, h, 0}}};
  j["outline"] = polyline(projector_, corners, false);
  const std::array<Eigen::Vector3d, 2> edge{{{0, h, 0}, {w, h, 0}}};
  j["bottom_edge"] = polyline(projector_, edge, false);
  json circles = json::array();
  for (int i = 0; i < 4; ++i) {
    const double u = pose_->circles_px[static_cast<size_t>(2 * i)];
    const double v = pose_->circles_px[static_cast<size_t>(2 * i + 1)];
    if (pose_->valid && std::isfinite(u) && std::isfinite(v)) circles.push_back({r1(u), r1(v)});
  }
  j["circles_px"] = circles;
  return j;
}

json CatchDisplayState::world_json(int64_t now_us) const {
  if (!world_) return nullptr;
  const auto& w = *world_;
  const double r = board_.ball_radius_mm(), h = board_.height_mm;
  json j = {{"status", world_status(w.status)},
            {"ball_id", w.ball_id},
            {"reason", w.reason},
            {"has_prediction", w.has_prediction},
            {"latency_ms", r1(w.latency_ms)},
            {"age_ms", r1(age_ms(world_us_, now_us))}};
  const bool has_state = finite2(w.position_b_mm) && finite2(w.velocity_b_mm_s);
  if (has_state) {
    j["position_b_mm"] = {r1(w.position_b_mm[0]), r1(w.position_b_mm[1])};
    j["velocity_b_mm_s"] = {r1(w.velocity_b_mm_s[0]), r1(w.velocity_b_mm_s[1])};
    j["ball_px"] = point(projector_.project_board({w.position_b_mm[0], w.position_b_mm[1], r}));
  }
  if (!w.has_prediction || !std::isfinite(w.exit_x_b_mm)) return j;
  j["exit_x_b_mm"] = r1(w.exit_x_b_mm);
  j["exit_sigma_mm"] = r1(w.exit_sigma_mm);
  j["exit_sigma_s"] = rounded(w.exit_sigma_s, 3);
  j["exit_in_s"] = rounded(seconds_between(now_us, w.exit_utime), 2);
  j["exit_px"] = point(projector_.project_board({w.exit_x_b_mm, h, r}));
  const double sigma = std::isfinite(w.exit_sigma_mm) ? w.exit_sigma_mm : 0.0;
  const std::array<Eigen::Vector3d, 2> span{
      {{w.exit_x_b_mm - sigma, h, r}, {w.exit_x_b_mm + sigma, h, r}}};
  j["exit_span_px"] = polyline(projector_, span, false);
  if (has_state) {
    // The path the world model predicts: x + vx t, y + vy t + a t^2 / 2 with
    // the a that reaches the bottom edge at its exit time.
    const double x = w.position_b_mm[0], y = w.position_b_mm[1];
    const double vx = w.velocity_b_mm_s[0], vy = w.velocity_b_mm_s[1];
    const double tau = seconds_between(w.utime, w.exit_utime);
    std::vector<Eigen::Vector3d> path;
    path.emplace_back(x, y, r);
    if (tau > 1e-3 && y < h) {
      const double a = std::max(0.0, 2.0 * (h - y - vy * tau) / (tau * tau));
      for (int i = 1; i < options_.path_points; ++i) {
        const double t = tau * i / options_.path_points;
        path.emplace_back(x + vx * t, y + vy * t + 0.5 * a * t * t, r);
      }
    }
    path.emplace_back(w.exit_x_b_mm, h, r);
    j["path_px"] = polyline(projector_, path, false);
  }
  const Eigen::Vector3d c(w.catch_point_w_mm[0], w.catch_point_w_mm[1], w.catch_point_w_mm[2]);
  if (c.allFinite()) {
    j["catch_point_w_mm"] = {r1(c.x()), r1(c.y()), r1(c.z())};
    j["catch_px"] = point(projector_.project_world(c));
    j["catch_in_s"] = rounded(seconds_between(now_us, w.catch_utime), 2);
  }
  return j;
}

json CatchDisplayState::arm_json(int64_t now_us) const {
  if (!arm_) return nullptr;
  const auto& a = *arm_;
  json j = {{"x_mm", r1(a.x_mm)},
            {"y_mm", r1(a.y_mm)},
            {"z_mm", r1(a.z_mm)},
            {"moving", a.moving},
            {"speed_mm_s", r1(a.speed_mm_s)},
            {"age_ms", r1(age_ms(arm_us_, now_us))}};
  const Eigen::Vector3d tip(a.x_mm, a.y_mm, a.z_mm);
  j["cup_px"] = point(projector_.project_world(tip));
  // The cup's opening: a horizontal circle of W around the tool tip.
  std::vector<Eigen::Vector3d> rim;
  for (int i = 0; i <= options_.rim_points; ++i) {
    const double phi = 2.0 * kPi * i / options_.rim_points;
    rim.push_back(tip + options_.cup.inner_radius_mm *
                            Eigen::Vector3d(std::cos(phi), std::sin(phi), 0.0));
  }
  j["rim_px"] = polyline(projector_, rim, true);
  return j;
}

json CatchDisplayState::to_json(int64_t now_us) const {
  json j;
  j["frame"] = {{"index", frame_index_},
                {"width", width_px_},
                {"height", height_px_},
                {"age_ms", r1(age_ms(frame_us_, now_us))}};
  j["board"] = board_json(now_us);
  j["surveyed"] = surveyed_;
  if (ball_) {
    const auto& b = *ball_;
    j["ball"] = {{"frame_index", b.frame_index},
                 {"found", b.found},
                 {"u", r1(b.u)},
                 {"v", r1(b.v)},
                 {"u_blob", r1(b.u_blob)},
                 {"v_blob", r1(b.v_blob)},
                 {"area_px", b.area_px},
                 {"window", b.window},
                 {"exec_ms", rounded(b.exec_ms, 2)},
                 {"age_ms", r1(age_ms(ball_us_, now_us))}};
  } else {
    j["ball"] = nullptr;
  }
  j["world"] = world_json(now_us);
  j["arm"] = arm_json(now_us);
  if (truth_) {
    const auto& t = *truth_;
    json jt = {{"ball", t.ball},
               {"phase", truth_phase(t.phase)},
               {"incline_deg", r1(t.incline_deg)},
               {"last_ball", t.last_ball},
               {"last_caught", t.last_caught},
               {"last_oracle_reachable", t.last_oracle_reachable},
               {"last_reason", t.last_reason},
               {"age_ms", r1(age_ms(truth_us_, now_us))}};
    jt["ball_px"] = finite2(t.ball_px) ? json::array({r1(t.ball_px[0]), r1(t.ball_px[1])}) : json();
    j["truth"] = jt;
    j["score"] = {
        {"balls", t.balls_done}, {"caught", t.caught}, {"oracle_reachable", t.oracle_reachable}};
  } else {
    j["truth"] = nullptr;
    j["score"] = nullptr;
  }
  return j;
}

}  // namespace ephor::catch_display
