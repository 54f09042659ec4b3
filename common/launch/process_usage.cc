#include "common/launch/process_usage.h"

#include <dirent.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

namespace ephor::deputy {
namespace {

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "";
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

pid_t parent_of(pid_t pid) {
  const std::string stat = read_file("/proc/" + std::to_string(pid) + "/stat");
  const auto close = stat.rfind(')');
  if (close == std::string::npos) return 0;
  std::istringstream rest(stat.substr(close + 1));
  std::string state;
  pid_t ppid = 0;
  rest >> state >> ppid;
  return ppid;
}

}  // namespace

std::optional<int64_t> parse_stat_cpu_ticks(const std::string& stat_line) {
  const auto close = stat_line.rfind(')');
  if (close == std::string::npos) return std::nullopt;
  std::istringstream rest(stat_line.substr(close + 1));
  // After the name: field 3 (state) .. field 15 (stime); utime is the 12th of them.
  std::string field;
  int64_t utime = 0;
  int64_t stime = 0;
  for (int i = 3; i <= 13; ++i)
    if (!(rest >> field)) return std::nullopt;
  if (!(rest >> utime >> stime) || utime < 0 || stime < 0) return std::nullopt;
  return utime + stime;
}

std::optional<UsageSample> ProcessUsage::sample(pid_t pid, int64_t now_ns) {
  const std::string base = "/proc/" + std::to_string(pid);
  const auto ticks = parse_stat_cpu_ticks(read_file(base + "/stat"));
  if (!ticks) return std::nullopt;
  UsageSample s;
  std::istringstream statm(read_file(base + "/statm"));
  int64_t size_pages = 0;
  int64_t resident_pages = 0;
  if (statm >> size_pages >> resident_pages) s.rss_bytes = resident_pages * sysconf(_SC_PAGESIZE);
  auto it = previous_.find(pid);
  if (it != previous_.end() && now_ns > it->second.at_ns) {
    const double cpu_s = static_cast<double>(*ticks - it->second.cpu_ticks) /
                         static_cast<double>(sysconf(_SC_CLK_TCK));
    const double wall_s = static_cast<double>(now_ns - it->second.at_ns) * 1e-9;
    s.cpu_percent = static_cast<float>(100.0 * cpu_s / wall_s);
  }
  previous_[pid] = {*ticks, now_ns};
  return s;
}

void ProcessUsage::forget_others(const std::vector<pid_t>& alive) {
  for (auto it = previous_.begin(); it != previous_.end();) {
    bool keep = false;
    for (pid_t p : alive) keep = keep || p == it->first;
    it = keep ? std::next(it) : previous_.erase(it);
  }
}

std::string process_comm(pid_t pid) {
  std::string comm = read_file("/proc/" + std::to_string(pid) + "/comm");
  while (!comm.empty() && comm.back() == '\n') comm.pop_back();
  return comm;
}

std::vector<pid_t> find_leftovers(const std::string& env_name, const std::string& env_value,
                                  const std::string& live_parent_comm) {
  std::vector<pid_t> found;
  const std::string wanted = env_name + "=" + env_value;
  DIR* dir = opendir("/proc");
  if (dir == nullptr) return found;
  while (const dirent* e = readdir(dir)) {
    char* end = nullptr;
    const long pid = std::strtol(e->d_name, &end, 10);
    if (end == e->d_name || *end != '\0' || pid <= 0 || pid == getpid()) continue;
    const std::string environ = read_file("/proc/" + std::string(e->d_name) + "/environ");
    bool tagged = false;
    for (size_t pos = 0; pos < environ.size() && !tagged;) {
      const size_t nul = environ.find('\0', pos);
      const size_t len = (nul == std::string::npos ? environ.size() : nul) - pos;
      tagged = environ.compare(pos, len, wanted) == 0;
      pos += len + 1;
    }
    if (!tagged) continue;
    const pid_t ppid = parent_of(static_cast<pid_t>(pid));
    if (ppid > 0 && process_comm(ppid) == live_parent_comm) continue;  // a live deputy's child
    found.push_back(static_cast<pid_t>(pid));
  }
  closedir(dir);
  return found;
}

}  // namespace ephor::deputy
