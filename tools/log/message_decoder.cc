#include "tools/log/message_decoder.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <vector>

namespace ephor::logtools {
namespace {

std::string hex(uint64_t v) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "0x%016llx", static_cast<unsigned long long>(v));
  return buf;
}

// Reads big-endian fields from a buffer; every read is bounds-checked.
class Reader {
 public:
  Reader(const uint8_t* data, size_t size, const std::string& type)
      : data_(data), size_(size), type_(type) {}

  uint64_t read_be(size_t n, const std::string& field) {
    need(n, field);
    uint64_t v = 0;
    for (size_t i = 0; i < n; ++i) v = (v << 8) | data_[pos_ + i];
    pos_ += n;
    return v;
  }
  std::string read_string(const std::string& field) {
    const auto len = static_cast<int32_t>(read_be(4, field));
    if (len < 1) fail(field, "string length " + std::to_string(len) + " < 1");
    need(static_cast<size_t>(len), field);
    // The length counts the terminating NUL.
    std::string s(reinterpret_cast<const char*>(data_ + pos_), static_cast<size_t>(len - 1));
    pos_ += static_cast<size_t>(len);
    return s;
  }
  size_t remaining() const { return size_ - pos_; }
  [[noreturn]] void fail(const std::string& field, const std::string& why) const {
    throw DecodeError(type_ + "." + field + " at byte " + std::to_string(pos_) + ": " + why);
  }

 private:
  void need(size_t n, const std::string& field) const {
    if (size_ - pos_ < n)
      fail(field, "message truncated (" + std::to_string(size_) + " bytes, needs " +
                      std::to_string(pos_ + n) + ")");
  }
  const uint8_t* data_;
  size_t size_;
  std::string type_;
  size_t pos_ = 0;
};

class StructDecoder {
 public:
  StructDecoder(const LcmSchema& schema, const DecodeOptions& options, Reader& in)
      : schema_(schema), options_(options), in_(in) {}

  Json decode_struct(const LcmStruct& s) {
    Json out = Json::object();
    for (const auto& m : s.members) {
      std::vector<int64_t> dims;
      for (const auto& d : m.dimensions) {
        int64_t n = d.fixed_size;
        if (d.variable) {
          n = out.at(d.size).get<int64_t>();
          if (n < 0) in_.fail(m.name, "array size " + d.size + " = " + std::to_string(n) + " < 0");
        }
        dims.push_back(n);
      }
      if (m.type == "byte" && dims.size() == 1 && !options_.include_bytes) {
        // Skip the bytes without materialising them.
        for (int64_t i = 0; i < dims[0]; ++i) in_.read_be(1, m.name);
        out[m.name] = "<" + std::to_string(dims[0]) + " bytes>";
        continue;
      }
      out[m.name] = decode_array(m, dims, 0);
    }
    return out;
  }

 private:
  Json decode_array(const LcmMember& m, const std::vector<int64_t>& dims, size_t level) {
    if (level == dims.size()) return decode_one(m);
    Json arr = Json::array();
    for (int64_t i = 0; i < dims[level]; ++i) arr.push_back(decode_array(m, dims, level + 1));
    return arr;
  }

  static Json number(double v) {
    // JSON has no NaN/inf: keep them readable as strings rather than fail.
    if (std::isfinite(v)) return v;
    return std::isnan(v) ? "nan" : (v > 0 ? "inf" : "-inf");
  }

  // The shortest decimal that reads back as the same float, as a double: a
  // float32 402.46573 would otherwise print as 402.4657287597656.
  static double shortest(float f) {
    if (!std::isfinite(f)) return static_cast<double>(f);
    char buf[32];
    for (int digits = 6; digits < 9; ++digits) {
      std::snprintf(buf, sizeof buf, "%.*g", digits, static_cast<double>(f));
      if (std::strtof(buf, nullptr) == f) return std::strtod(buf, nullptr);
    }
    return static_cast<double>(f);
  }

  Json decode_one(const LcmMember& m) {
    const std::string& t = m.type;
    if (t == "int8_t") return static_cast<int8_t>(in_.read_be(1, m.name));
    if (t == "byte") return static_cast<uint8_t>(in_.read_be(1, m.name));
    if (t == "boolean") return in_.read_be(1, m.name) != 0;
    if (t == "int16_t") return static_cast<int16_t>(in_.read_be(2, m.name));
    if (t == "int32_t") return static_cast<int32_t>(in_.read_be(4, m.name));
    if (t == "int64_t") return static_cast<int64_t>(in_.read_be(8, m.name));
    if (t == "float") {
      const auto bits = static_cast<uint32_t>(in_.read_be(4, m.name));
      float f;
      std::memcpy(&f, &bits, sizeof f);
      return number(shortest(f));
    }
    if (t == "double") {
      const uint64_t bits = in_.read_be(8, m.name);
      double d;
      std::memcpy(&d, &bits, sizeof d);
      return number(d);
    }
    if (t == "string") return in_.read_string(m.name);
    const LcmStruct* nested = schema_.find(t);
    if (nested == nullptr) in_.fail(m.name, "unknown type " + t);
    return decode_struct(*nested);
  }

  const LcmSchema& schema_;
  const DecodeOptions& options_;
  Reader& in_;
};

uint64_t read_fingerprint(const void* data, size_t size) {
  if (size < 8)
    throw DecodeError("message of " + std::to_string(size) + " bytes has no 8-byte fingerprint");
  uint64_t v = 0;
  for (size_t i = 0; i < 8; ++i) v = (v << 8) | static_cast<const uint8_t*>(data)[i];
  return v;
}

}  // namespace

DecodedMessage MessageDecoder::decode(const void* data, size_t size) const {
  const uint64_t fp = read_fingerprint(data, size);
  const LcmStruct* type = schema_.find_by_fingerprint(fp);
  if (type == nullptr)
    throw DecodeError("no type in lcmtypes/ has fingerprint " + hex(fp) +
                      " (a foreign type, or a log recorded with other versions of our types)");
  return {type, decode_as(*type, data, size)};
}

Json MessageDecoder::decode_as(const LcmStruct& type, const void* data, size_t size) const {
  const uint64_t fp = read_fingerprint(data, size);
  if (fp != schema_.fingerprint(type.full_name()))
    throw DecodeError("fingerprint " + hex(fp) + " is not " + type.full_name() + "'s " +
                      hex(schema_.fingerprint(type.full_name())));
  Reader in(static_cast<const uint8_t*>(data) + 8, size - 8, type.full_name());
  Json out = StructDecoder(schema_, options_, in).decode_struct(type);
  if (in.remaining() != 0)
    throw DecodeError(type.full_name() + ": " + std::to_string(in.remaining()) +
                      " byte(s) left over after the last field");
  return out;
}

}  // namespace ephor::logtools
