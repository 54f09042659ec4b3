#include "common/launch/usage_log.h"

#include <algorithm>

#include <fmt/format.h>

namespace ephor::launcher {

namespace {

constexpr double kMb = 1024.0 * 1024.0;

}  // namespace

UsageLog::UsageLog(double warmup_s) : warmup_s_(std::max(0.0, warmup_s)) {}

void UsageLog::add(const std::string& name, double t_s, double cpu_percent, int64_t rss_bytes) {
  samples_[name].push_back({t_s, cpu_percent, rss_bytes});
}

std::vector<UsageSummary> UsageLog::summaries() const {
  std::vector<UsageSummary> out;
  for (const auto& [name, v] : samples_) {
    UsageSummary s;
    s.name = name;
    s.samples = static_cast<int>(v.size());
    if (v.empty()) {
      out.push_back(s);
      continue;
    }
    s.span_s = v.back().t_s - v.front().t_s;
    for (size_t i = 1; i < v.size(); ++i)
      s.cpu_s += v[i].cpu_percent / 100.0 * (v[i].t_s - v[i - 1].t_s);
    s.cpu_percent_mean = s.span_s > 0.0 ? 100.0 * s.cpu_s / s.span_s : 0.0;
    s.rss_last_bytes = v.back().rss_bytes;
    for (const auto& x : v) s.rss_max_bytes = std::max(s.rss_max_bytes, x.rss_bytes);

    // After the warm-up: the first RSS and the least-squares slope.
    const double settled_from = v.front().t_s + warmup_s_;
    std::vector<const Sample*> settled;
    for (const auto& x : v)
      if (x.t_s >= settled_from) settled.push_back(&x);
    s.rss_first_bytes = settled.empty() ? v.front().rss_bytes : settled.front()->rss_bytes;
    if (settled.size() >= 3) {
      double mt = 0.0, mr = 0.0;
      for (const auto* x : settled) {
        mt += x->t_s;
        mr += static_cast<double>(x->rss_bytes);
      }
      mt /= static_cast<double>(settled.size());
      mr /= static_cast<double>(settled.size());
      double stt = 0.0, str = 0.0;
      for (const auto* x : settled) {
        stt += (x->t_s - mt) * (x->t_s - mt);
        str += (x->t_s - mt) * (static_cast<double>(x->rss_bytes) - mr);
      }
      if (stt > 0.0) s.rss_growth_bytes_per_hour = str / stt * 3600.0;
    }
    out.push_back(s);
  }
  return out;
}

nlohmann::json to_json(const UsageLog& log) {
  nlohmann::json processes = nlohmann::json::array();
  for (const auto& s : log.summaries()) {
    processes.push_back(
        {{"name", s.name},
         {"samples", s.samples},
         {"span_s", s.span_s},
         {"cpu_s", s.cpu_s},
         {"cpu_percent_mean", s.cpu_percent_mean},
         {"rss_first_mb", static_cast<double>(s.rss_first_bytes) / kMb},
         {"rss_last_mb", static_cast<double>(s.rss_last_bytes) / kMb},
         {"rss_max_mb", static_cast<double>(s.rss_max_bytes) / kMb},
         {"rss_growth_mb_per_hour", s.rss_growth_bytes_per_hour
                                        ? nlohmann::json(*s.rss_growth_bytes_per_hour / kMb)
                                        : nlohmann::json(nullptr)}});
  }
  return {{"warmup_s", log.warmup_s()}, {"processes", processes}};
}

std::vector<std::string> format_table(const UsageLog& log) {
  const auto all = log.summaries();
  size_t width = 7;
  for (const auto& s : all) width = std::max(width, s.name.size());
  std::vector<std::string> lines;
  lines.push_back(fmt::format("{:<{}}  {:>9} {:>9} {:>9} {:>12} {:>9} {:>6}", "process", width,
                              "rss MB", "last", "max", "growth MB/h", "cpu s", "cpu %"));
  for (const auto& s : all) {
    const std::string growth = s.rss_growth_bytes_per_hour
                                   ? fmt::format("{:+.1f}", *s.rss_growth_bytes_per_hour / kMb)
                                   : std::string("-");
    lines.push_back(fmt::format(
        "{:<{}}  {:>9.1f} {:>9.1f} {:>9.1f} {:>12} {:>9.1f} {:>6.1f}", s.name, width,
        static_cast<double>(s.rss_first_bytes) / kMb, static_cast<double>(s.rss_last_bytes) / kMb,
        static_cast<double>(s.rss_max_bytes) / kMb, growth, s.cpu_s, s.cpu_percent_mean));
  }
  return lines;
}

}  // namespace ephor::launcher
