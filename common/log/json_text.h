#pragma once
// JSON as text, for every summary file, page and log line that carries
// strings from the bus. An LCM string is any bytes (a host name, a task name,
// a reason), and nlohmann's dump() throws type_error 316 on one that is not
// UTF-8: a run summary would be lost at exit, a page would answer 500 until
// the sender spoke again. Here such bytes are written as U+FFFD instead.

#include <string>

#include <nlohmann/json.hpp>

namespace ephor {

// `indent` as nlohmann's dump(): -1 one line, >= 0 pretty with that indent.
inline std::string json_text(const nlohmann::json& j, int indent = -1) {
  return j.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace ephor
