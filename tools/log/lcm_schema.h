#pragma once
// LcmSchema: the message types of lcmtypes/*.lcm read at run time, so that a
// log can be decoded without code generated for each type (tools/ephor log
// export decodes "any of our types", including fields added after the tool
// was built).
//
// Each struct's fingerprint is computed as lcm-gen 1.3.1 computes it (the
// member names, primitive type names and dimensions, plus the fingerprints of
// nested structs, rotated left by one bit), so a message on the wire is
// matched to its type by its first 8 bytes, as lcm-spy does. The unit test
// checks the fingerprints against every type lcm-gen generated for C++.
//
// Supported: the subset of the LCM type language our types use and a bit
// more: `package`, `struct`, primitive members, nested structs, fixed and
// variable (named by an earlier integer member) array dimensions, and `const`
// declarations (ignored, they are not on the wire). Enums are refused with a
// clear error.

#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace ephor::logtools {

// A .lcm file that does not parse, or a struct that names a missing type.
class SchemaError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct LcmDimension {
  bool variable = false;  // size given by another member
  std::string size;       // the number (fixed) or that member's name (variable)
  int fixed_size = 0;     // when !variable
};

struct LcmMember {
  std::string type;  // primitive ("int32_t", "float", "string", ...) or full struct name
  std::string name;
  std::vector<LcmDimension> dimensions;  // outermost first
  bool primitive() const;
};

struct LcmStruct {
  std::string package;  // "ephor"
  std::string name;     // short name, "shepherd_objects_t"
  std::string file;     // where it was defined
  std::vector<LcmMember> members;
  std::string full_name() const { return package.empty() ? name : package + "." + name; }
};

class LcmSchema {
 public:
  // Parses every *.lcm file in `dir`. Throws SchemaError naming the file and
  // line of the first problem, or when `dir` holds no .lcm file.
  static LcmSchema load_directory(const std::string& dir);

  // Parses one file's text (`file` names it in errors). Call resolve() when
  // every file is added.
  void add_text(const std::string& text, const std::string& file);
  // Checks that every struct member's type exists and computes the
  // fingerprints. Throws SchemaError.
  void resolve();

  // By full ("ephor.shepherd_objects_t") or short ("shepherd_objects_t") name; nullptr if none.
  const LcmStruct* find(const std::string& name) const;
  // The struct whose fingerprint (the first 8 bytes of an encoded message,
  // big-endian) is `fingerprint`; nullptr if none.
  const LcmStruct* find_by_fingerprint(uint64_t fingerprint) const;
  // lcm-gen's getHash() of the struct (full name). Throws std::out_of_range.
  uint64_t fingerprint(const std::string& full_name) const;
  std::vector<std::string> names() const;  // full names, sorted

 private:
  uint64_t compute_hash(const LcmStruct& s, std::vector<std::string>& parents) const;

  std::map<std::string, LcmStruct> structs_;  // by full name
  std::map<uint64_t, std::string> by_fingerprint_;
  std::map<std::string, uint64_t> fingerprints_;
};

// The hash of the members only (lcm-gen's lcm_struct_hash), before nested
// types are added; exposed for the tests.
uint64_t lcm_base_hash(const LcmStruct& s);

}  // namespace ephor::logtools
