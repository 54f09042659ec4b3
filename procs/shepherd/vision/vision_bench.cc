// ephor-bench-vision: the shepherding paper's Figure 14 (blobify vs trackify
// at sampling steps k = 4, 8, 10, 12 on 512 x 482 frames with six marks of
// about 16 px), measured on this machine, with OpenCV's threshold +
// connectedComponentsWithStats on the same frames as the peer.
//
// Frames are rendered here with a fixed seed: a dark field (grey 40) with
// Gaussian pixel noise, six antialiased marks (grey 200, 16 px diameter),
// each drifting at 0.2-1.5 px/frame inside its own sixth of the image, so
// every frame has marks at new sub-pixel positions and trackify has a
// previous frame to start from. The threshold is picked once from the first
// frame's histogram (the paper's rule). Centroid error is measured against
// the rendered centres.
//
//   ephor-bench-vision [--frames 300] [--passes 5] [--seed 1] [--noise 4] [--cache warm|cold]
//                      [--no-rt] [--json FILE]
//
// Timing runs under SCHED_FIFO on one CPU when allowed (as ephor-vision runs
// under ephor-scheduler), so other processes do not preempt the timed calls;
// --no-rt times under SCHED_OTHER.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <new>
#include <random>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "common/runtime/process_args.h"
#include "common/runtime/thread_sched.h"
#include "common/shepherd/vision/blobifier.h"
#include "common/shepherd/vision/synthetic_image.h"
#include "common/shepherd/vision/threshold_selector.h"
#include "common/shepherd/vision/trackifier.h"

// Counts heap allocations, to show that blobify/trackify allocate nothing per
// frame in steady state.
namespace {
std::atomic<uint64_t> g_allocations{0};
}  // namespace
void* operator new(std::size_t n) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n == 0 ? 1 : n)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace ephor::vision {
namespace {

constexpr int kWidth = 512;
constexpr int kHeight = 482;
constexpr int kMarks = 6;
constexpr double kRadius = 8.0;  // px: 16 px diameter marks
constexpr float kField = 40.0f;
constexpr float kMark = 200.0f;
constexpr double kMatchPx = 4.0;  // a blob within this distance of a true centre matches it

struct Truth {
  double u, v;
};

struct Scene {
  std::vector<std::vector<uint8_t>> frames;
  std::vector<std::vector<Truth>> truth;
};

Scene render_scene(int n_frames, uint32_t seed, double noise) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  // Each mark drifts inside its own cell of a 3 x 2 grid, bouncing off the
  // cell's walls, so marks never touch.
  struct Mark {
    double u, v, du, dv, u_lo, u_hi, v_lo, v_hi;
  };
  std::vector<Mark> marks;
  const double cw = static_cast<double>(kWidth) / 3.0, ch = static_cast<double>(kHeight) / 2.0;
  for (int i = 0; i < kMarks; ++i) {
    Mark m{};
    m.u_lo = (i % 3) * cw + kRadius + 2.0;
    m.u_hi = (i % 3 + 1) * cw - kRadius - 2.0;
    m.v_lo = (i / 3) * ch + kRadius + 2.0;
    m.v_hi = (i / 3 + 1) * ch - kRadius - 2.0;
    m.u = m.u_lo + uni(rng) * (m.u_hi - m.u_lo);
    m.v = m.v_lo + uni(rng) * (m.v_hi - m.v_lo);
    const double speed = 0.2 + 1.3 * uni(rng), dir = 2.0 * M_PI * uni(rng);
    m.du = speed * std::cos(dir);
    m.dv = speed * std::sin(dir);
    marks.push_back(m);
  }
  Scene s;
  SyntheticImage img(kWidth, kHeight, kField);
  for (int f = 0; f < n_frames; ++f) {
    img.fill(kField);
    std::vector<Truth> t;
    for (Mark& m : marks) {
      img.add_disc(m.u, m.v, kRadius, kMark);
      t.push_back({m.u, m.v});
      m.u += m.du;
      m.v += m.dv;
      if (m.u < m.u_lo || m.u > m.u_hi) m.du = -m.du;
      if (m.v < m.v_lo || m.v > m.v_hi) m.dv = -m.dv;
    }
    img.render(noise, rng);
    s.frames.push_back(img.pixels());
    s.truth.push_back(std::move(t));
  }
  return s;
}

ImageView view_of(const std::vector<uint8_t>& px) {
  return ImageView{px.data(), kWidth, kHeight, kWidth};
}

// Where the timed call finds its frame. Warm: the frame is first copied (not
// timed) into one working buffer, as ephor-vision copies each frame out of
// LCM's receive buffer just before searching it, so it sits in the cache.
// Cold: the call reads the frame where it was rendered; the sequence (tens
// of MB) is far larger than the caches, so every frame comes from DRAM.
bool g_warm = true;
std::vector<uint8_t> g_work(static_cast<size_t>(kWidth) * kHeight);

ImageView frame_for_call(const std::vector<uint8_t>& px) {
  if (!g_warm) return view_of(px);
  std::copy(px.begin(), px.end(), g_work.begin());
  return view_of(g_work);
}

struct Accuracy {
  double sum_sq = 0.0;
  int64_t matched = 0;
  int64_t missed = 0;
  int64_t extra = 0;
  void add(const std::vector<Truth>& truth, const std::vector<Blob>& blobs) {
    std::vector<bool> used(blobs.size(), false);
    for (const Truth& t : truth) {
      int best = -1;
      double best_d2 = kMatchPx * kMatchPx;
      for (size_t i = 0; i < blobs.size(); ++i) {
        const double du = static_cast<double>(blobs[i].u) - t.u;
        const double dv = static_cast<double>(blobs[i].v) - t.v;
        const double d2 = du * du + dv * dv;
        if (!used[i] && d2 < best_d2) {
          best_d2 = d2;
          best = static_cast<int>(i);
        }
      }
      if (best < 0) {
        ++missed;
      } else {
        used[static_cast<size_t>(best)] = true;
        sum_sq += best_d2;
        ++matched;
      }
    }
    for (bool u : used) extra += u ? 0 : 1;
  }
  double rms() const {
    return matched > 0 ? std::sqrt(sum_sq / static_cast<double>(matched))
                       : std::numeric_limits<double>::quiet_NaN();
  }
};

struct Row {
  std::string method;
  int k = 0;
  std::vector<double> us;  // time per frame, us
  Accuracy acc;
  double allocs_per_frame = 0.0;  // steady state (after the first pass)
  double paper_ms = std::numeric_limits<double>::quiet_NaN();
};

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  const size_t i =
      std::min(v.size() - 1, static_cast<size_t>(std::ceil(p * static_cast<double>(v.size()))) - 1);
  return v[i];
}

double mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return v.empty() ? std::numeric_limits<double>::quiet_NaN() : s / static_cast<double>(v.size());
}

using Clock = std::chrono::steady_clock;
double us_since(Clock::time_point t0, Clock::time_point t1) {
  return std::chrono::duration<double, std::micro>(t1 - t0).count();
}

Row bench_blobify(const Scene& s, int k, ScanMode scan, uint8_t thr, int passes) {
  Row row;
  row.method = scan == ScanMode::kFull ? "blobify" : "blobify-axis";
  row.k = k;
  row.us.reserve(static_cast<size_t>(passes) * s.frames.size());
  BlobifierConfig cfg;
  cfg.sample_step = k;
  Blobifier b(cfg);
  uint64_t allocs = 0;
  for (int p = 0; p < passes; ++p) {
    const uint64_t a0 = g_allocations.load();
    for (size_t f = 0; f < s.frames.size(); ++f) {
      const ImageView frame = frame_for_call(s.frames[f]);
      const auto t0 = Clock::now();
      const auto& blobs = b.blobify(frame, thr, scan);
      const auto t1 = Clock::now();
      row.us.push_back(us_since(t0, t1));
      if (p == 0) row.acc.add(s.truth[f], blobs);
    }
    if (p > 0) allocs += g_allocations.load() - a0;
  }
  if (passes > 1)
    row.allocs_per_frame =
        static_cast<double>(allocs) / static_cast<double>((passes - 1) * s.frames.size());
  return row;
}

Row bench_trackify(const Scene& s, int k, ScanMode scan, uint8_t thr, int passes) {
  Row row;
  row.method = scan == ScanMode::kFull ? "trackify" : "trackify-axis";
  row.k = k;
  row.us.reserve(static_cast<size_t>(passes) * s.frames.size());
  BlobifierConfig cfg;
  cfg.sample_step = k;
  Blobifier b(cfg);
  TrackifierConfig tc;
  tc.full_every = 0;  // pure trackify after the first frame, as in the paper's table
  Trackifier t(tc);
  uint64_t allocs = 0;
  for (int p = 0; p < passes; ++p) {
    t.reset();  // the sequence restarts: the first frame is a full blobify (not timed)
    const uint64_t a0 = g_allocations.load();
    for (size_t f = 0; f < s.frames.size(); ++f) {
      const ImageView frame = frame_for_call(s.frames[f]);
      const auto t0 = Clock::now();
      const auto& blobs = t.track(b, frame, thr, scan);
      const auto t1 = Clock::now();
      if (!t.last_was_full()) row.us.push_back(us_since(t0, t1));
      if (p == 0) row.acc.add(s.truth[f], blobs);
    }
    if (p > 0) allocs += g_allocations.load() - a0;
  }
  if (passes > 1)
    row.allocs_per_frame =
        static_cast<double>(allocs) / static_cast<double>((passes - 1) * s.frames.size());
  return row;
}

Row bench_opencv(const Scene& s, uint8_t thr, int min_area, int passes, int connectivity) {
  Row row;
  row.method = connectivity == 4 ? "opencv-cc4" : "opencv-cc8";
  row.us.reserve(static_cast<size_t>(passes) * s.frames.size());
  row.k = 1;
  cv::Mat bin(kHeight, kWidth, CV_8U), labels, stats, centroids;
  std::vector<Blob> blobs;
  for (int p = 0; p < passes; ++p) {
    for (size_t f = 0; f < s.frames.size(); ++f) {
      const ImageView frame = frame_for_call(s.frames[f]);
      const cv::Mat src(kHeight, kWidth, CV_8U, const_cast<uint8_t*>(frame.data));
      const auto t0 = Clock::now();
      cv::threshold(src, bin, thr, 255, cv::THRESH_BINARY);
      const int n =
          cv::connectedComponentsWithStats(bin, labels, stats, centroids, connectivity, CV_32S);
      const auto t1 = Clock::now();
      row.us.push_back(us_since(t0, t1));
      if (p == 0) {
        blobs.clear();
        for (int i = 1; i < n; ++i) {
          if (stats.at<int>(i, cv::CC_STAT_AREA) < min_area) continue;
          Blob bl;
          bl.u = static_cast<float>(centroids.at<double>(i, 0));
          bl.v = static_cast<float>(centroids.at<double>(i, 1));
          bl.area = stats.at<int>(i, cv::CC_STAT_AREA);
          blobs.push_back(bl);
        }
        row.acc.add(s.truth[f], blobs);
      }
    }
  }
  row.allocs_per_frame = std::numeric_limits<double>::quiet_NaN();
  return row;
}

}  // namespace
}  // namespace ephor::vision

int main(int argc, char** argv) {
  using namespace ephor::vision;
  CLI::App app{"ephor-bench-vision: the paper's Figure 14 (blobify vs trackify) on this machine"};
  int frames = 300, passes = 5;
  uint32_t seed = 1;
  double noise = 4.0;
  std::string json_path;
  app.add_option("--frames", frames, "frames in the rendered sequence")->check(CLI::Range(2, 5000));
  app.add_option("--passes", passes, "timed passes over the sequence")->check(CLI::Range(1, 100));
  app.add_option("--seed", seed, "random seed of the scene and the noise");
  app.add_option("--noise", noise, "pixel noise, grey levels (sd)")->check(CLI::Range(0.0, 40.0));
  app.add_option("--json", json_path, "write the table as JSON to this file");
  std::string cache = "warm";
  app.add_option("--cache", cache,
                 "warm: copy each frame into a working buffer before the timed call (as "
                 "ephor-vision does); cold: read it from the rendered sequence (DRAM)")
      ->check(CLI::IsMember({"warm", "cold"}));
  bool no_rt = false;
  app.add_flag(
      "--no-rt", no_rt,
      "time under SCHED_OTHER (default: SCHED_FIFO 10 on CPU 1 while timing, as "
      "ephor-vision runs under the scheduler, so other processes' jobs do not preempt it)");
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  g_warm = cache == "warm";
  try {
    cv::setNumThreads(1);  // one core each: the machine is shared and our search is single-threaded
    std::printf(
        "rendering %d frames of %d x %d px, %d marks of %.0f px, noise sd %.1f, seed %u ...\n",
        frames, kWidth, kHeight, kMarks, 2.0 * kRadius, noise, seed);
    const Scene scene = render_scene(frames, seed, noise);
    const ThresholdChoice choice = ThresholdSelector().select(view_of(scene.frames[0]));
    if (choice.status != ThresholdStatus::kOk) {
      std::fprintf(stderr, "threshold selection failed: %s\n", choice.message.c_str());
      return 1;
    }
    const auto thr = static_cast<uint8_t>(choice.threshold);
    bool rt = false;
    if (!no_rt) {
      const ephor::SchedOutcome o = ephor::apply_to_calling_thread(
          {std::min(1, ephor::online_cpus() - 1), ephor::Policy::kFifo, 10});
      rt = o.policy_ok;
      if (!o.error.empty()) std::printf("warning: %s\n", o.error.c_str());
    }
    std::printf("timing under %s\n", rt ? "SCHED_FIFO 10" : "SCHED_OTHER");
    std::printf("threshold %d (field peak %d, mark peak %d)\n", choice.threshold,
                choice.background_peak, choice.object_peak);

    const double paper_blobify[] = {26, 17, 12, 9};
    const double paper_trackify[] = {18, 8, 4, 3};
    const int ks[] = {4, 8, 10, 12};
    std::vector<Row> rows;
    for (int i = 0; i < 4; ++i) {
      Row b = bench_blobify(scene, ks[i], ScanMode::kFull, thr, passes);
      b.paper_ms = paper_blobify[i];
      rows.push_back(std::move(b));
      Row t = bench_trackify(scene, ks[i], ScanMode::kFull, thr, passes);
      t.paper_ms = paper_trackify[i];
      rows.push_back(std::move(t));
    }
    for (int k : ks) rows.push_back(bench_blobify(scene, k, ScanMode::kAxis, thr, passes));
    for (int k : ks) rows.push_back(bench_trackify(scene, k, ScanMode::kAxis, thr, passes));
    rows.push_back(bench_opencv(scene, thr, BlobifierConfig{}.min_area, passes, 4));
    rows.push_back(bench_opencv(scene, thr, BlobifierConfig{}.min_area, passes, 8));

    std::printf("\n%-14s %3s %9s %9s %9s %9s %8s %7s %6s %9s %9s\n", "method", "k", "mean_us",
                "p50_us", "p99_us", "max_us", "rms_px", "missed", "extra", "allocs/f", "paper_ms");
    nlohmann::json out;
    out["frame"] = {{"width", kWidth}, {"height", kHeight}};
    out["marks"] = kMarks;
    out["mark_diameter_px"] = 2.0 * kRadius;
    out["frames"] = frames;
    out["passes"] = passes;
    out["seed"] = seed;
    out["noise_sd"] = noise;
    out["threshold"] = choice.threshold;
    out["cache"] = cache;
    out["sched_fifo"] = rt;
    out["rows"] = nlohmann::json::array();
    for (const Row& r : rows) {
      const double m = mean(r.us), p50 = percentile(r.us, 0.5), p99 = percentile(r.us, 0.99),
                   mx = percentile(r.us, 1.0);
      char paper[32] = "-";
      if (!std::isnan(r.paper_ms)) std::snprintf(paper, sizeof paper, "%.0f", r.paper_ms);
      char allocs[32] = "-";
      if (!std::isnan(r.allocs_per_frame))
        std::snprintf(allocs, sizeof allocs, "%.2f", r.allocs_per_frame);
      std::printf("%-14s %3d %9.1f %9.1f %9.1f %9.0f %8.3f %7lld %6lld %9s %9s\n", r.method.c_str(),
                  r.k, m, p50, p99, mx, r.acc.rms(), static_cast<long long>(r.acc.missed),
                  static_cast<long long>(r.acc.extra), allocs, paper);
      nlohmann::json j = {{"method", r.method},
                          {"k", r.k},
                          {"mean_us", m},
                          {"p50_us", p50},
                          {"p99_us", p99},
                          {"max_us", mx},
                          {"samples", r.us.size()},
                          {"rms_px", r.acc.rms()},
                          {"matched", r.acc.matched},
                          {"missed", r.acc.missed},
                          {"extra", r.acc.extra}};
      if (!std::isnan(r.allocs_per_frame)) j["allocs_per_frame"] = r.allocs_per_frame;
      if (!std::isnan(r.paper_ms)) j["paper_ms"] = r.paper_ms;
      out["rows"].push_back(j);
    }
    std::printf(
        "\nmissed/extra: true marks with no blob within %.0f px / blobs with no mark "
        "(over the first pass, %d frames x %d marks).\ntrackify times exclude the sequence's "
        "first frame (a full blobify). opencv-ccN = cv::threshold + "
        "cv::connectedComponentsWithStats (4- / 8-connectivity, 1 thread).\n"
        "cache: %s (see --help). allocs/f: heap allocations per frame after the first pass.\n",
        kMatchPx, frames, kMarks, cache.c_str());
    if (!json_path.empty()) {
      std::ofstream f(json_path);
      if (!f) {
        std::fprintf(stderr, "cannot write %s\n", json_path.c_str());
        return 1;
      }
      f << out.dump(2) << "\n";
      std::printf("wrote %s\n", json_path.c_str());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ephor-bench-vision: %s\n", e.what());
    return 1;
  }
  return 0;
}
