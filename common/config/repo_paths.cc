#include "common/config/repo_paths.h"

#include <cstdlib>

namespace ephor {

std::filesystem::path repo_dir() {
  if (const char* env = std::getenv("EPHOR_SOURCE_DIR"); env != nullptr && *env != '\0') return env;
  std::error_code ec;
#ifdef EPHOR_BUILT_FROM
  if (std::filesystem::exists(std::filesystem::path(EPHOR_BUILT_FROM) / "deploy", ec))
    return EPHOR_BUILT_FROM;
#endif
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return ".";
  return exe.parent_path().parent_path().parent_path();
}

std::string default_calibration_path() {
  return (repo_dir() / "deploy" / "calibration" / "sim.pbtxt").string();
}

std::string resolve_repo_path(const std::string& path) {
  const std::filesystem::path p(path);
  if (path.empty() || p.is_absolute() || std::filesystem::exists(p)) return path;
  return (repo_dir() / p).string();
}

}  // namespace ephor
