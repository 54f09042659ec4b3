#include "tools/log/log_exporter.h"

#include <algorithm>
#include <climits>
#include <cstdio>
#include <iomanip>
#include <memory>
#include <regex>
#include <sstream>

#include <lcm/lcm-cpp.hpp>

namespace ephor::logtools {
namespace {

// A string field that is not UTF-8 (a corrupt or foreign message) is written
// with U+FFFD for its bad bytes: nlohmann's dump() would throw and end the
// whole export (found by the fuzz target lcm_log, issue 18).
std::string dump_text(const Json& v) {
  return v.dump(-1, ' ', false, Json::error_handler_t::replace);
}

constexpr size_t kMaxErrorsKept = 5;
constexpr int kMaxExpandedFixedArray = 16;  // larger fixed arrays go into one cell
// LCM publishes one message of its own here when a process opens the bus
// (liblcm's self test); it is no type of ours and not worth an error.
constexpr const char* kLcmSelfTest = "LCM_SELF_TEST";

// One CSV column: where its value is in the decoded message.
struct Column {
  std::string name;
  std::vector<std::string> path;  // member names and array indices (digits)
  bool in_element = false;        // path is relative to the exploded array's element
  bool joined = false;            // an array: its numbers joined by spaces, else JSON
};

class CsvLayout {
 public:
  CsvLayout(const LcmSchema& schema, const LcmStruct& type) : schema_(schema) {
    // The first variable-length array of structs at the top is exploded.
    for (const auto& m : type.members)
      if (!m.primitive() && m.dimensions.size() == 1 && m.dimensions[0].variable) {
        explode_ = m.name;
        break;
      }
    for (const auto& m : type.members) {
      if (m.name == explode_) continue;
      add(m, "", {}, false);
    }
    if (!explode_.empty()) {
      const LcmStruct* element = schema_.find(
          std::find_if(type.members.begin(), type.members.end(), [&](const LcmMember& m) {
            return m.name == explode_;
          })->type);
      for (const auto& m : element->members) add(m, explode_ + ".", {}, true);
    }
  }

  void write_header(std::ostream& out) const {
    out << "log_utime_us,channel";
    for (const auto& c : columns_) out << ',' << csv_quote(c.name);
    out << '\n';
  }

  // Returns the rows written.
  int64_t write_rows(std::ostream& out, int64_t log_utime, const std::string& channel,
                     const Json& msg) const {
    const Json* elements = explode_.empty() ? nullptr : &msg.at(explode_);
    const size_t n = elements == nullptr ? 1 : std::max<size_t>(1, elements->size());
    for (size_t i = 0; i < n; ++i) {
      out << log_utime << ',' << csv_quote(channel);
      const Json* element = elements != nullptr && i < elements->size() ? &(*elements)[i] : nullptr;
      for (const auto& c : columns_) {
        out << ',';
        const Json* root = c.in_element ? element : &msg;
        if (root != nullptr) out << csv_quote(cell(*root, c));
      }
      out << '\n';
    }
    return static_cast<int64_t>(n);
  }

 private:
  void add(const LcmMember& m, const std::string& prefix, std::vector<std::string> path,
           bool in_element) {
    path.push_back(m.name);
    const std::string name = prefix + m.name;
    if (m.dimensions.empty()) {
      if (m.primitive()) {
        columns_.push_back({name, path, in_element, false});
      } else {
        for (const auto& sub : schema_.find(m.type)->members)
          add(sub, name + ".", path, in_element);
      }
      return;
    }
    const auto& d = m.dimensions[0];
    if (m.dimensions.size() == 1 && m.primitive() && m.type != "byte" && !d.variable &&
        d.fixed_size <= kMaxExpandedFixedArray) {
      for (int i = 0; i < d.fixed_size; ++i) {
        auto p = path;
        p.push_back(std::to_string(i));
        columns_.push_back({name + "[" + std::to_string(i) + "]", p, in_element, false});
      }
      return;
    }
    columns_.push_back({name, path, in_element, m.primitive() && m.dimensions.size() == 1});
  }

  static std::string scalar(const Json& v) {
    if (v.is_string()) return v.get<std::string>();
    if (v.is_boolean()) return v.get<bool>() ? "1" : "0";
    return dump_text(v);
  }

  static std::string cell(const Json& root, const Column& c) {
    const Json* v = &root;
    for (const auto& key : c.path) {
      if (v->is_array())
        v = &(*v)[std::stoul(key)];
      else
        v = &v->at(key);
    }
    if (!v->is_array()) return scalar(*v);
    if (!c.joined) return dump_text(*v);
    std::string s;
    for (const auto& x : *v) s += (s.empty() ? "" : " ") + scalar(x);
    return s;
  }

  const LcmSchema& schema_;
  std::string explode_;
  std::vector<Column> columns_;
};

std::regex make_regex(const std::string& pattern) {
  try {
    return std::regex(pattern, std::regex::extended);
  } catch (const std::regex_error& e) {
    throw ExportError("bad channel regular expression '" + pattern + "': " + e.what());
  }
}

}  // namespace

std::string csv_quote(const std::string& cell) {
  if (cell.find_first_of(",\"\n\r") == std::string::npos) return cell;
  std::string out = "\"";
  for (char c : cell) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

LogExporter::LogExporter(const LcmSchema& schema, ExportOptions options)
    : schema_(schema), options_(std::move(options)) {
  if (options_.include_bytes && options_.format == ExportFormat::kCsv)
    throw ExportError("byte arrays in full are for JSON only, not CSV");
}

ExportStats LogExporter::run(const std::string& log_path, std::ostream& out) const {
  const std::regex channels = make_regex(options_.channel_regex);
  lcm::LogFile log(log_path, "r");
  if (!log.good()) throw ExportError("cannot open LCM log " + log_path);
  MessageDecoder decoder(schema_, {options_.include_bytes});
  ExportStats stats;
  const LcmStruct* csv_type = nullptr;
  std::unique_ptr<CsvLayout> layout;
  while (const lcm::LogEvent* e = log.readNextEvent()) {
    ++stats.events;
    if (!std::regex_match(e->channel, channels) || e->channel == kLcmSelfTest) continue;
    DecodedMessage msg;
    try {
      msg = decoder.decode(e->data, static_cast<size_t>(e->datalen));
    } catch (const DecodeError& err) {
      ++stats.undecodable;
      if (stats.first_errors.size() < kMaxErrorsKept)
        stats.first_errors.push_back(e->channel + " (event " + std::to_string(e->eventnum) +
                                     "): " + err.what());
      continue;
    }
    ++stats.exported;
    if (options_.format == ExportFormat::kJsonLines) {
      Json line = Json::object();
      line["log_utime_us"] = e->timestamp;
      line["channel"] = e->channel;
      line["type"] = msg.type->full_name();
      line["msg"] = std::move(msg.fields);
      out << dump_text(line) << '\n';
      ++stats.rows;
      continue;
    }
    if (csv_type == nullptr) {
      csv_type = msg.type;
      layout = std::make_unique<CsvLayout>(schema_, *csv_type);
      layout->write_header(out);
    } else if (csv_type != msg.type) {
      throw ExportError("CSV needs one message type, but channel " + e->channel + " carries " +
                        msg.type->full_name() + " after " + csv_type->full_name() +
                        ": export one channel, or use --json");
    }
    stats.rows += layout->write_rows(out, e->timestamp, e->channel, msg.fields);
  }
  return stats;
}

std::vector<ChannelSummary> summarize_log(const LcmSchema& schema, const std::string& log_path) {
  lcm::LogFile log(log_path, "r");
  if (!log.good()) throw ExportError("cannot open LCM log " + log_path);
  MessageDecoder decoder(schema);
  std::map<std::string, ChannelSummary> by_channel;
  std::map<std::pair<std::string, std::string>, int64_t> last_seq;  // (channel, sender)
  while (const lcm::LogEvent* e = log.readNextEvent()) {
    auto& s = by_channel[e->channel];
    if (s.count == 0) {
      s.channel = e->channel;
      s.first_utime_us = e->timestamp;
      s.type = "?";
    }
    ++s.count;
    s.bytes += e->datalen;
    s.last_utime_us = e->timestamp;
    if (e->channel == kLcmSelfTest) {
      s.type = "(liblcm self test)";
      continue;
    }
    DecodedMessage msg;
    try {
      msg = decoder.decode(e->data, static_cast<size_t>(e->datalen));
    } catch (const DecodeError&) {
      ++s.undecodable;
      continue;
    }
    s.type = msg.type->full_name();
    const auto h = msg.fields.find("header");
    if (h == msg.fields.end() || !h->is_object() || !h->contains("seq") || !h->contains("sender"))
      continue;
    const auto key = std::make_pair(e->channel, h->at("sender").get<std::string>());
    const auto seq = h->at("seq").get<int64_t>();
    if (const auto it = last_seq.find(key); it != last_seq.end()) {
      if (seq <= it->second) {
        ++s.repeated;
        continue;
      }
      // The gap in unsigned arithmetic, saturated: a corrupt log's seqs can be
      // anything (signed overflow, found by the fuzz target lcm_log).
      const uint64_t gap = static_cast<uint64_t>(seq) - static_cast<uint64_t>(it->second) - 1;
      const auto room = static_cast<uint64_t>(INT64_MAX - s.missing);
      s.missing = gap > room ? INT64_MAX : s.missing + static_cast<int64_t>(gap);
    }
    last_seq[key] = seq;
  }
  std::vector<ChannelSummary> out;
  for (auto& [name, s] : by_channel) out.push_back(std::move(s));
  return out;
}

void print_summary(const std::vector<ChannelSummary>& channels, std::ostream& out) {
  int64_t first = INT64_MAX;
  int64_t last = INT64_MIN;
  int64_t total = 0;
  int64_t missing = 0;
  size_t width = 7;
  for (const auto& c : channels) {
    first = std::min(first, c.first_utime_us);
    last = std::max(last, c.last_utime_us);
    total += c.count;
    missing += c.missing;
    width = std::max(width, c.channel.size());
  }
  char buf[256];
  out << std::left << std::setw(static_cast<int>(width)) << "channel"
      << "  type                         count    rate/Hz   mean/kB  missing  repeated\n";
  for (const auto& c : channels) {
    // In double: a corrupt log's times can be anything, their difference too
    // (signed overflow, found by the fuzz target lcm_log).
    const double span_s =
        (static_cast<double>(c.last_utime_us) - static_cast<double>(c.first_utime_us)) * 1e-6;
    const double rate = span_s > 0 ? static_cast<double>(c.count - 1) / span_s : 0.0;
    std::snprintf(
        buf, sizeof buf, "  %-26s %8lld %10.1f %9.1f %8lld %9lld%s", c.type.c_str(),
        static_cast<long long>(c.count), rate,
        static_cast<double>(c.bytes) / static_cast<double>(c.count) / 1000.0,
        static_cast<long long>(c.missing), static_cast<long long>(c.repeated),
        c.undecodable > 0 ? ("  (" + std::to_string(c.undecodable) + " undecodable)").c_str() : "");
    out << std::left << std::setw(static_cast<int>(width)) << c.channel << buf << '\n';
  }
  std::snprintf(
      buf, sizeof buf, "%zu channels, %lld messages over %.1f s; %lld missing by header.seq\n",
      channels.size(), static_cast<long long>(total),
      channels.empty() ? 0.0 : (static_cast<double>(last) - static_cast<double>(first)) * 1e-6,
      static_cast<long long>(missing));
  out << buf;
}

}  // namespace ephor::logtools
