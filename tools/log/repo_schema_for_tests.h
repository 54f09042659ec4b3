#pragma once
// The repository's lcmtypes/ as a schema, loaded once, for the logtools tests
// ($EPHOR_SOURCE_DIR, set by ephor_test(), else the working directory).

#include <cstdlib>
#include <string>

#include "tools/log/lcm_schema.h"

namespace ephor::logtools {

inline std::string repo_lcmtypes_dir() {
  const char* src = std::getenv("EPHOR_SOURCE_DIR");
  return std::string(src != nullptr ? src : ".") + "/lcmtypes";
}

inline const LcmSchema& repo_schema() {
  static const LcmSchema s = LcmSchema::load_directory(repo_lcmtypes_dir());
  return s;
}

}  // namespace ephor::logtools
