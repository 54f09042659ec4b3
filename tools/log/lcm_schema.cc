#include "tools/log/lcm_schema.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace ephor::logtools {
namespace {

const char* const kPrimitives[] = {"int8_t", "int16_t", "int32_t", "int64_t", "byte",
                                   "float",  "double",  "string",  "boolean"};

bool is_primitive(const std::string& t) {
  return std::any_of(std::begin(kPrimitives), std::end(kPrimitives),
                     [&](const char* p) { return t == p; });
}

bool is_dimension_type(const std::string& t) {
  return t == "int8_t" || t == "int16_t" || t == "int32_t" || t == "int64_t";
}

// lcm-gen's hash step. It works on a signed 64-bit value: the right shift
// sign-extends, and each character is added as a (signed) char.
int64_t hash_update(int64_t v, char c) {
  const auto left = static_cast<int64_t>(static_cast<uint64_t>(v) << 8);
  return static_cast<int64_t>(static_cast<uint64_t>(left ^ (v >> 55)) +
                              static_cast<uint64_t>(static_cast<int64_t>(c)));
}

int64_t hash_string_update(int64_t v, const std::string& s) {
  v = hash_update(v, static_cast<char>(s.size()));
  for (char c : s) v = hash_update(v, c);
  return v;
}

struct Token {
  std::string text;
  int line = 0;
};

// Splits .lcm text into identifiers/numbers and one-character punctuation,
// dropping // and /* */ comments.
std::vector<Token> tokenize(const std::string& text, const std::string& file) {
  std::vector<Token> out;
  int line = 1;
  size_t i = 0;
  while (i < text.size()) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
      ++i;
    } else if (std::isspace(static_cast<unsigned char>(c))) {
      ++i;
    } else if (c == '/' && i + 1 < text.size() && text[i + 1] == '/') {
      while (i < text.size() && text[i] != '\n') ++i;
    } else if (c == '/' && i + 1 < text.size() && text[i + 1] == '*') {
      const size_t end = text.find("*/", i + 2);
      if (end == std::string::npos)
        throw SchemaError(file + ":" + std::to_string(line) + ": unterminated /* comment");
      line += static_cast<int>(std::count(text.begin() + static_cast<long>(i),
                                          text.begin() + static_cast<long>(end), '\n'));
      i = end + 2;
    } else if (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.' ||
               c == '+') {
      size_t j = i + 1;
      while (j < text.size() &&
             (std::isalnum(static_cast<unsigned char>(text[j])) || text[j] == '_' ||
              text[j] == '.' ||
              ((text[j] == '-' || text[j] == '+') && (text[j - 1] == 'e' || text[j - 1] == 'E'))))
        ++j;
      out.push_back({text.substr(i, j - i), line});
      i = j;
    } else if (std::strchr("{}[];,=", c) != nullptr) {
      out.push_back({std::string(1, c), line});
      ++i;
    } else {
      throw SchemaError(file + ":" + std::to_string(line) + ": unexpected character '" +
                        std::string(1, c) + "'");
    }
  }
  return out;
}

class Parser {
 public:
  Parser(std::vector<Token> tokens, std::string file)
      : tokens_(std::move(tokens)), file_(std::move(file)) {}

  std::vector<LcmStruct> parse() {
    std::vector<LcmStruct> out;
    std::string package;
    while (!at_end()) {
      const std::string word = next("'package' or 'struct'");
      if (word == "package") {
        package = next("a package name");
        expect(";");
      } else if (word == "struct") {
        out.push_back(parse_struct(package));
      } else if (word == "enum") {
        fail("enums are not supported by this decoder");
      } else {
        fail("expected 'package' or 'struct', got '" + word + "'");
      }
    }
    return out;
  }

 private:
  LcmStruct parse_struct(const std::string& package) {
    LcmStruct s;
    s.package = package;
    s.name = next("a struct name");
    s.file = file_;
    expect("{");
    while (peek() != "}") {
      const std::string type = next("a member type or 'const'");
      if (type == "const") {
        skip_const();
        continue;
      }
      while (true) {
        LcmMember m;
        m.type = is_primitive(type) || type.find('.') != std::string::npos
                     ? type
                     : (package.empty() ? type : package + "." + type);
        m.name = next("a member name");
        if (!(std::isalpha(static_cast<unsigned char>(m.name[0])) || m.name[0] == '_'))
          fail("bad member name '" + m.name + "'");
        for (const auto& other : s.members)
          if (other.name == m.name) fail("duplicate member '" + m.name + "'");
        while (peek() == "[") {
          expect("[");
          LcmDimension d;
          d.size = next("an array size");
          if (std::isdigit(static_cast<unsigned char>(d.size[0]))) {
            d.fixed_size = std::stoi(d.size);
          } else {
            d.variable = true;
            const auto it = std::find_if(s.members.begin(), s.members.end(),
                                         [&](const LcmMember& o) { return o.name == d.size; });
            if (it == s.members.end() || !it->dimensions.empty() || !is_dimension_type(it->type))
              fail("array size '" + d.size + "' of '" + m.name +
                   "' must be an earlier integer member");
          }
          expect("]");
          m.dimensions.push_back(d);
        }
        s.members.push_back(m);
        if (peek() == ",") {
          expect(",");
          continue;
        }
        expect(";");
        break;
      }
    }
    expect("}");
    return s;
  }

  void skip_const() {
    next("a const type");
    while (true) {
      next("a const name");
      expect("=");
      next("a const value");
      if (peek() != ",") break;
      expect(",");
    }
    expect(";");
  }

  bool at_end() const { return pos_ >= tokens_.size(); }
  std::string peek() const { return at_end() ? std::string() : tokens_[pos_].text; }
  std::string next(const std::string& what) {
    if (at_end()) fail("end of file while looking for " + what);
    return tokens_[pos_++].text;
  }
  void expect(const std::string& tok) {
    const std::string got = next("'" + tok + "'");
    if (got != tok) {
      --pos_;
      fail("expected '" + tok + "', got '" + got + "'");
    }
  }
  [[noreturn]] void fail(const std::string& why) const {
    const int line = tokens_.empty() ? 0 : tokens_[std::min(pos_, tokens_.size() - 1)].line;
    throw SchemaError(file_ + ":" + std::to_string(line) + ": " + why);
  }

  std::vector<Token> tokens_;
  std::string file_;
  size_t pos_ = 0;
};

}  // namespace

bool LcmMember::primitive() const { return is_primitive(type); }

uint64_t lcm_base_hash(const LcmStruct& s) {
  int64_t v = 0x12345678;
  for (const auto& m : s.members) {
    v = hash_string_update(v, m.name);
    if (m.primitive()) v = hash_string_update(v, m.type);
    v = hash_update(v, static_cast<char>(m.dimensions.size()));
    for (const auto& d : m.dimensions) {
      v = hash_update(v, d.variable ? 1 : 0);  // lcm-gen's LCM_CONST = 0, LCM_VAR = 1
      v = hash_string_update(v, d.size);
    }
  }
  return static_cast<uint64_t>(v);
}

LcmSchema LcmSchema::load_directory(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw SchemaError("lcm types folder " + dir + " does not exist");
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".lcm") files.push_back(e.path());
  if (files.empty()) throw SchemaError("no .lcm file in " + dir);
  std::sort(files.begin(), files.end());
  LcmSchema schema;
  for (const auto& f : files) {
    std::ifstream in(f);
    std::stringstream ss;
    ss << in.rdbuf();
    if (!in) throw SchemaError("cannot read " + f.string());
    schema.add_text(ss.str(), f.string());
  }
  schema.resolve();
  return schema;
}

void LcmSchema::add_text(const std::string& text, const std::string& file) {
  for (auto& s : Parser(tokenize(text, file), file).parse()) {
    const std::string name = s.full_name();
    if (structs_.count(name))
      throw SchemaError(file + ": struct " + name + " is also defined in " +
                        structs_.at(name).file);
    structs_.emplace(name, std::move(s));
  }
}

void LcmSchema::resolve() {
  for (const auto& [name, s] : structs_)
    for (const auto& m : s.members)
      if (!m.primitive() && !structs_.count(m.type))
        throw SchemaError(s.file + ": member '" + m.name + "' of " + name + " has unknown type " +
                          m.type);
  fingerprints_.clear();
  by_fingerprint_.clear();
  for (const auto& [name, s] : structs_) {
    std::vector<std::string> parents;
    const uint64_t h = compute_hash(s, parents);
    fingerprints_[name] = h;
    by_fingerprint_[h] = name;
  }
}

// The generated _computeHash(): the member hash plus each nested struct
// member's hash (0 for a type already on the path: recursion), rotated left
// by one bit.
uint64_t LcmSchema::compute_hash(const LcmStruct& s, std::vector<std::string>& parents) const {
  const std::string name = s.full_name();
  if (std::find(parents.begin(), parents.end(), name) != parents.end()) return 0;
  parents.push_back(name);
  uint64_t h = lcm_base_hash(s);
  for (const auto& m : s.members)
    if (!m.primitive()) h += compute_hash(structs_.at(m.type), parents);
  parents.pop_back();
  return (h << 1) + ((h >> 63) & 1);
}

const LcmStruct* LcmSchema::find(const std::string& name) const {
  if (auto it = structs_.find(name); it != structs_.end()) return &it->second;
  for (const auto& [full, s] : structs_)
    if (s.name == name) return &s;
  return nullptr;
}

const LcmStruct* LcmSchema::find_by_fingerprint(uint64_t fingerprint) const {
  const auto it = by_fingerprint_.find(fingerprint);
  return it == by_fingerprint_.end() ? nullptr : &structs_.at(it->second);
}

uint64_t LcmSchema::fingerprint(const std::string& full_name) const {
  return fingerprints_.at(full_name);
}

std::vector<std::string> LcmSchema::names() const {
  std::vector<std::string> out;
  for (const auto& [name, s] : structs_) out.push_back(name);
  return out;
}

}  // namespace ephor::logtools
