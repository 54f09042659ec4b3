#include "procs/stripe/planner/plan_task.h"

#include <fstream>
#include <utility>
#include <variant>

#include <spdlog/spdlog.h>

namespace ephor::stripe {
namespace {

// Paper 004, section 5: "a system such as we are discussing should be able to
// image 3 or 4 stripes of 256 three-dimensional points per second if
// scanning is done in a regular raster".
constexpr double kPaperStripesPerS = 3.5;

}  // namespace

PlanTask::PlanTask(PlanTaskConfig config, PlanOutputs& out, int64_t first_id)
    : config_(std::move(config)), out_(out), next_goal_(first_id), next_request_(first_id) {}

void PlanTask::publish_scan(double t_s) {
  stripe_scan_t m = scan_message_of(*seq_, config_.spec, scan_id_, t_s);
  m.utime = config_.wall_us();
  out_.scan(m);
  last_status_s_ = t_s;
}

void PlanTask::act(const SequencerActions& a, double t_s) {
  if (seq_->range_losses() != last_range_losses_) {
    last_range_losses_ = seq_->range_losses();
    spdlog::warn(
        "scan {}: the range process has lost stripes it had ranged (restarted?): they will be "
        "taken again",
        scan_id_);
  }
  if (seq_->retaken() != last_retaken_) {
    spdlog::warn("scan {}: going back for {} stripes without points", scan_id_,
                 seq_->retaken() - last_retaken_);
    last_retaken_ = seq_->retaken();
  }
  if (a.goal) {
    if (a.goal->stripe == last_goal_stripe_)
      spdlog::warn("stripe {}: its goal sent again as goal {}", a.goal->stripe, a.goal->goal_id);
    last_goal_stripe_ = a.goal->stripe;
    arm_goal_t g = goal_message_of(*a.goal, config_.speed_mm_s);
    g.utime = config_.wall_us();
    out_.goal(*a.goal, g);
  }
  if (a.capture) {
    stripe_capture_t c = capture_message_of(*a.capture, scan_id_);
    c.utime = config_.wall_us();
    out_.capture(*a.capture, c);
  }
  if (a.changed) publish_scan(t_s);
}

void PlanTask::finish_scan(double t_s) {
  const double per_stripe_us =
      cpu_.extract_n > 0 && cpu_.range_n > 0
          ? cpu_.extract_cpu_us / cpu_.extract_n + cpu_.range_cpu_us / cpu_.range_n
          : 0.0;
  const RasterSpec& spec = config_.spec;
  summary_ = {
      {"system", "stripe"},
      {"scan_id", scan_id_},
      {"state", to_string(seq_->state())},
      {"reason", seq_->reason()},
      {"robot_seed", config_.robot_seed},
      {"calibration", config_.calibration_name},
      {"region_mm", {spec.x0_mm, spec.y0_mm, spec.x1_mm, spec.y1_mm}},
      {"step_mm", spec.step_mm},
      {"height_mm", spec.height_mm},
      {"stripes_planned", seq_->planned()},
      {"stripes_captured", seq_->captured()},
      {"stripes_skipped", seq_->skipped()},
      {"stripes_retaken", seq_->retaken()},
      {"range_losses", seq_->range_losses()},
      {"stripes_missing_in_cloud", last_cloud_.stripes_missing},
      {"cloud_points", seq_->cloud_points()},
      {"cloud_path", last_cloud_.path},
      {"elapsed_s", seq_->elapsed_s(t_s)},
      {"motion_s", seq_->motion_s()},
      {"stripes_per_s_scanned", seq_->stripes_per_s()},
      {"paper_stripes_per_s", kPaperStripesPerS},
      {"processing_cpu_us_per_stripe", per_stripe_us},
      {"extract_cpu_us_per_stripe",
       cpu_.extract_n > 0 ? cpu_.extract_cpu_us / cpu_.extract_n : 0.0},
      {"range_cpu_us_per_stripe", cpu_.range_n > 0 ? cpu_.range_cpu_us / cpu_.range_n : 0.0}};
  if (seq_->state() == ScanState::kDone) {
    spdlog::info(
        "scan {} done: {} of {} stripes ({} skipped, {} taken again), {} points in {:.1f} s: "
        "{:.2f} stripes/s scanned with the arm moving (paper: 3-4), arm moving {:.1f} s, "
        "processing {:.0f} us CPU a stripe",
        scan_id_, seq_->captured(), seq_->planned(), seq_->skipped(), seq_->retaken(),
        seq_->cloud_points(), seq_->elapsed_s(t_s), seq_->stripes_per_s(), seq_->motion_s(),
        per_stripe_us);
  } else {
    spdlog::error("scan {} failed: {}", scan_id_, seq_->reason());
  }
  if (!config_.summary_path.empty()) {
    std::ofstream out(config_.summary_path);
    out << summary_.dump(2) << "\n";
    if (!out) spdlog::error("could not write the summary to {}", config_.summary_path);
  }
}

bool PlanTask::new_scan(double t_s, const arm::Joints& from) {
  // Planned again from where the arm is (the same plan from the start
  // configuration; after a scan, from its last stripe).
  try {
    plan_ = config_.plan(from);
  } catch (const PlanError& e) {
    spdlog::error("{}", e.what());
    return false;
  }
  scan_id_ = config_.wall_us();
  seq_.emplace(plan_.goals, next_goal_, next_request_);
  last_goal_stripe_ = -1;
  last_retaken_ = last_range_losses_ = 0;
  cpu_ = ScanCpu{};
  last_cloud_ = CloudEvent{};
  const RasterSpec& spec = config_.spec;
  spdlog::info(
      "scan {}: {} stripes {:g} mm apart over ({:g}, {:g}) - ({:g}, {:g}) mm, {:g} mm up; {}",
      scan_id_, plan_.goals.size(), spec.step_mm, spec.x0_mm, spec.y0_mm, spec.x1_mm, spec.y1_mm,
      spec.height_mm, config_.calibration_measured);
  act(seq_->start(t_s), t_s);
  publish_scan(t_s);
  return true;
}

void PlanTask::run(double t_s, const std::vector<PlanEvent>& events,
                   const std::optional<arm::Joints>& arm_q, bool arm_moving) {
  if (finished_) return;
  if (!seq_) {
    if (!arm_q) return;  // no arm state yet (comm holds goals until it has one too)
    if (!new_scan(t_s, *arm_q)) {
      exit_code_ = 1;
      finished_ = true;
      return;
    }
  }
  for (const PlanEvent& e : events) {
    if (const auto* d = std::get_if<DoneEvent>(&e);
        d && d->status == motion_done_t::STATUS_REJECTED)
      spdlog::warn("goal {} refused by the arm: {} (its stripe is skipped)", d->goal_id, d->reason);
    apply_event(*seq_, scan_id_, e, t_s, cpu_, &last_cloud_,
                [&](const SequencerActions& a) { act(a, t_s); });
  }
  if (arm_moving) seq_->on_arm_moving(t_s);
  act(seq_->tick(t_s), t_s);
  if (t_s - last_status_s_ >= 1.0) publish_scan(t_s);
  if (seq_->finished() && pause_until_s_ == 0.0) {
    finish_scan(t_s);
    next_goal_ = seq_->next_goal_id();
    next_request_ = seq_->next_request_id();
    ++scans_done_;
    if (seq_->state() == ScanState::kFailed) {
      exit_code_ = 1;
      finished_ = true;
    } else if (config_.scans > 0 && scans_done_ >= config_.scans) {
      finished_ = true;
    } else {
      pause_until_s_ = t_s + config_.pause_s;
    }
  }
  if (pause_until_s_ > 0.0 && t_s >= pause_until_s_ && arm_q) {
    pause_until_s_ = 0.0;
    if (!new_scan(t_s, *arm_q)) {
      exit_code_ = 1;
      finished_ = true;
    }
  }
}

}  // namespace ephor::stripe
