#pragma once
// MessageDecoder: one encoded LCM message (fingerprint + fields, big-endian,
// as lcm-gen encodes) -> JSON, by the LcmSchema read from lcmtypes/*.lcm.
// Members keep their declaration order; nested structs are objects, arrays
// are arrays. Byte arrays (camera pixels) are replaced by a short note unless
// asked for: a 250 kB frame as a JSON number array is rarely what is wanted.

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "tools/log/lcm_schema.h"

namespace ephor::logtools {

using Json = nlohmann::ordered_json;

// A message that does not decode: unknown fingerprint, truncated, a negative
// array size, trailing bytes.
class DecodeError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct DecodeOptions {
  bool include_bytes = false;  // byte arrays as number arrays (else "<N bytes>")
};

struct DecodedMessage {
  const LcmStruct* type = nullptr;
  Json fields;
};

class MessageDecoder {
 public:
  explicit MessageDecoder(const LcmSchema& schema, DecodeOptions options = {})
      : schema_(schema), options_(options) {}

  // Finds the type by the message's fingerprint and decodes it. Throws
  // DecodeError.
  DecodedMessage decode(const void* data, size_t size) const;
  // Decodes as `type` (its fingerprint must match). Throws DecodeError.
  Json decode_as(const LcmStruct& type, const void* data, size_t size) const;

 private:
  const LcmSchema& schema_;
  DecodeOptions options_;
};

}  // namespace ephor::logtools
