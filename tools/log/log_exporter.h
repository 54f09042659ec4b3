#pragma once
// LogExporter: the messages of an LCM log (lcm-logger's format, read with
// lcm::LogFile) on the channels matching a regular expression, decoded by
// LcmSchema/MessageDecoder and written as
//   JSON lines: one object per message,
//     {"log_utime_us": T, "channel": "OBJECTS", "type": "ephor.shepherd_objects_t", "msg": {...}}
//     where T is when the logger received it (us since the Unix epoch);
//   CSV: a header row, then one row per message, or, for a message holding a
//     variable-length array of structs (shepherd_objects_t.objects, shepherd_ground_truth_t.sheep,
//     task_jobs_t.jobs, shepherd_blobs_t.blobs), one row per element with the
//     message's other fields repeated (a message whose array is empty still
//     gives one row, with the element's columns empty). Nested structs become
//     dotted columns (header.seq), small fixed arrays one column per element
//     (q[0]), other arrays one cell (numbers separated by spaces). CSV needs
//     all exported messages to be of one type.
//
// LogSummary: per channel, the message count, type, size and rate, and, for
// types carrying header_t, the gaps in each sender's sequence numbers: the
// messages the logger did not receive (dropped on the way). liblcm's own
// LCM_SELF_TEST messages are listed but not decoded, and never exported.

#include <cstdint>
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "tools/log/lcm_schema.h"
#include "tools/log/message_decoder.h"

namespace ephor::logtools {

enum class ExportFormat { kJsonLines, kCsv };

struct ExportOptions {
  std::string channel_regex = ".*";  // matched against the whole channel name
  ExportFormat format = ExportFormat::kJsonLines;
  bool include_bytes = false;  // byte arrays in full (JSON only)
};

struct ExportStats {
  int64_t events = 0;                     // events in the log
  int64_t exported = 0;                   // messages written
  int64_t rows = 0;                       // CSV rows or JSON lines written
  int64_t undecodable = 0;                // matching messages that did not decode
  std::vector<std::string> first_errors;  // the first few decode errors, with channel
};

// Thrown for an unreadable log, a bad regex, or CSV with mixed types.
class ExportError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class LogExporter {
 public:
  LogExporter(const LcmSchema& schema, ExportOptions options);
  ExportStats run(const std::string& log_path, std::ostream& out) const;

 private:
  const LcmSchema& schema_;
  ExportOptions options_;
};

struct ChannelSummary {
  std::string channel;
  std::string type;  // full name, or "?" when the fingerprint is unknown
  int64_t count = 0;
  int64_t bytes = 0;
  int64_t first_utime_us = 0;  // logger receive times
  int64_t last_utime_us = 0;
  // From header_t.seq per sender (types without a header: all 0).
  int64_t missing = 0;   // sequence numbers never logged
  int64_t repeated = 0;  // a sequence number logged again, or going back
  int64_t undecodable = 0;
};

// Reads the whole log. Throws ExportError if it cannot be read.
std::vector<ChannelSummary> summarize_log(const LcmSchema& schema, const std::string& log_path);
void print_summary(const std::vector<ChannelSummary>& channels, std::ostream& out);

// CSV cell quoting (RFC 4180), exposed for the tests.
std::string csv_quote(const std::string& cell);

}  // namespace ephor::logtools
