#pragma once
// UsageLog: each process's resident memory and CPU over a run, from periodic
// samples (the deputy's ProcessUsage reads them from /proc), for the
// launcher's end-of-run table and `--usage FILE`. People run the system for
// hours next to hardware; a leak or a runaway task shows here as resident
// memory that keeps growing after the warm-up, or as CPU creeping up.
//
// Memory growth is the least-squares slope of RSS against time over the
// samples taken after the warm-up (start-up allocations, page faults of
// first use and the allocator settling are not a leak). CPU time integrates
// the samples' "% of one CPU since the previous sample" over their
// intervals. A restarted process keeps its name: its samples continue the
// same series.
//
// Pure code (no /proc, no clock): times are whatever the caller passes, s.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace ephor::launcher {

struct UsageSummary {
  std::string name;
  int samples = 0;
  double span_s = 0.0;            // first to last sample, s
  double cpu_s = 0.0;             // CPU time over the samples, s
  double cpu_percent_mean = 0.0;  // cpu_s over span_s, % of one CPU (0 when span_s is 0)
  int64_t rss_first_bytes = 0;    // first sample after the warm-up (the first sample without one)
  int64_t rss_last_bytes = 0;
  int64_t rss_max_bytes = 0;
  // Slope of RSS over the samples after the warm-up, bytes per hour; nullopt
  // with fewer than three of them.
  std::optional<double> rss_growth_bytes_per_hour;
};

class UsageLog {
 public:
  // warmup_s: time after a process's first sample that the growth fit skips.
  explicit UsageLog(double warmup_s = 60.0);

  // One sample of process `name` at time t_s (s, non-decreasing per name).
  // cpu_percent: % of one CPU since that process's previous sample.
  void add(const std::string& name, double t_s, double cpu_percent, int64_t rss_bytes);

  // One summary per process name, in name order.
  std::vector<UsageSummary> summaries() const;

  double warmup_s() const { return warmup_s_; }

 private:
  struct Sample {
    double t_s;
    double cpu_percent;
    int64_t rss_bytes;
  };
  double warmup_s_;
  std::map<std::string, std::vector<Sample>> samples_;
};

// {"warmup_s": ..., "processes": [{"name", "samples", "span_s", "cpu_s",
// "cpu_percent_mean", "rss_first_mb", "rss_last_mb", "rss_max_mb",
// "rss_growth_mb_per_hour" (null when not fitted)}]}; MB = 2^20 bytes.
nlohmann::json to_json(const UsageLog& log);

// The end-of-run table, one line per process, with a heading line.
std::vector<std::string> format_table(const UsageLog& log);

}  // namespace ephor::launcher
